// Tests for SetupLogging: the default logger is named after the vehicle or service.
#include "runtime/logging.h"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

namespace fleetloc::runtime {
namespace {

TEST(SetupLogging, DefaultLoggerIsNamedAfterTheVehicle) {
  SetupLogging("agv-7");
  EXPECT_EQ(spdlog::default_logger()->name(), "agv-7");
  EXPECT_EQ(spdlog::get("agv-7"), spdlog::default_logger());
  EXPECT_EQ(spdlog::default_logger()->sinks().size(), 1u);
  spdlog::info("logging test line");
}

TEST(SetupLogging, CallingAgainReplacesTheDefaultLogger) {
  SetupLogging("tile-server");
  SetupLogging("tile-server");  // same name twice must not throw
  EXPECT_EQ(spdlog::default_logger()->name(), "tile-server");
  SetupLogging("");
  EXPECT_EQ(spdlog::default_logger()->name(), "fleetloc");
  EXPECT_EQ(spdlog::get("tile-server"), nullptr);
}

}  // namespace
}  // namespace fleetloc::runtime
