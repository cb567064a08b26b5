#include "core/util/log.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <string>

#include "core/util/error.h"

namespace mtg::log {
namespace {

// One stderr logger per process. It is created on first use, not at static-init time.
spdlog::logger& logger() {
  static std::shared_ptr<spdlog::logger> instance = [] {
    auto made = spdlog::stderr_color_mt("mtg");
    made->set_pattern("[%^%l%$] %v");
    made->set_level(spdlog::level::info);
    return made;
  }();
  return *instance;
}

}  // namespace

void set_level(Level level) {
  switch (level) {
    case Level::kDebug: logger().set_level(spdlog::level::debug); break;
    case Level::kInfo: logger().set_level(spdlog::level::info); break;
    case Level::kWarn: logger().set_level(spdlog::level::warn); break;
    case Level::kError: logger().set_level(spdlog::level::err); break;
    case Level::kOff: logger().set_level(spdlog::level::off); break;
  }
}

Level parse_level(std::string_view name) {
  if (name == "debug") return Level::kDebug;
  if (name == "info") return Level::kInfo;
  if (name == "warn") return Level::kWarn;
  if (name == "error") return Level::kError;
  if (name == "off") return Level::kOff;
  throw Error("unknown log level '" + std::string(name) + "' (use debug, info, warn, error, off)");
}

void set_role(std::string_view role) {
  logger().set_pattern("[%^%l%$] " + std::string(role) + ": %v");
}

void debug(std::string_view message) { logger().debug("{}", message); }
void info(std::string_view message) { logger().info("{}", message); }
void warn(std::string_view message) { logger().warn("{}", message); }
void error(std::string_view message) { logger().error("{}", message); }

}  // namespace mtg::log
