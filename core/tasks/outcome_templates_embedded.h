#pragma once
// The built-in Level 4 template library, embedded from core/tasks/templates/outcome_templates.json.

namespace mtg::tasks {
extern const char* const kOutcomeTemplatesJson;
}
