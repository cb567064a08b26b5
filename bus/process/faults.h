#pragma once
// Test hooks: MTG_FAULTS="<name>:<n>,<name>:<n>,..." asks a process to misbehave on purpose
// (drop or duplicate a message, lose a chunk) so the tests can see recovery end to end.

#include <string_view>

namespace mtg::process {

/// The number given for `name` in $MTG_FAULTS, or -1 when it is not named.
int fault_setting(std::string_view name);

/// True the first time any process asks for `mark` while $MTG_FAULT_MARKS names a folder (it
/// leaves a file there): a fault a restarted process must not repeat. False without the folder.
bool first_time_fault(std::string_view mark);

}  // namespace mtg::process
