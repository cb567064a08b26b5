#pragma once
// Which build of mtg is running: the project version and the git revision the sources were at
// when it was built ("unknown" for sources outside git; "-dirty" when they held changes). Run
// folders record both (docs/runtime.md, "Provenance").

namespace mtg {

const char* mtg_version();
const char* mtg_git_revision();

}  // namespace mtg
