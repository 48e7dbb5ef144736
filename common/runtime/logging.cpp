// spdlog default-logger setup.
#include "runtime/logging.h"

#include <spdlog/cfg/env.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <memory>

namespace fleetloc::runtime {

void SetupLogging(const std::string& name) {
  const std::string logger_name = name.empty() ? "fleetloc" : name;
  // Built directly rather than with spdlog::stderr_color_mt so that a second call with the same
  // name replaces the logger instead of throwing "logger with name already exists".
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  auto logger = std::make_shared<spdlog::logger>(logger_name, std::move(sink));
  logger->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%n] [%l] %v");
  logger->set_level(spdlog::level::info);
  spdlog::drop(logger_name);
  spdlog::set_default_logger(logger);  // also registers it under its name
  spdlog::cfg::load_env_levels();      // SPDLOG_LEVEL overrides the level of registered loggers
}

}  // namespace fleetloc::runtime
