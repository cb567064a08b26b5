#pragma once
// Thin logging front over spdlog, so that spdlog's headers stay in one translation unit.
// Everything goes to stderr; stdout is kept for a command's real output (JSON, tables).

#include <string_view>

namespace mtg::log {

enum class Level { kDebug, kInfo, kWarn, kError, kOff };

void set_level(Level level);
/// Parses "debug", "info", "warn", "error", "off"; throws mtg::Error otherwise.
Level parse_level(std::string_view name);
/// Prefix every line with a process role, e.g. "judge".
void set_role(std::string_view role);

void debug(std::string_view message);
void info(std::string_view message);
void warn(std::string_view message);
void error(std::string_view message);

}  // namespace mtg::log
