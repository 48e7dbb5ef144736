// JSON text from outside bytes: invalid UTF-8 is replaced, never thrown (found by fuzz_http_api:
// a request path with such bytes ended in the error message of the 400 answer and aborted the
// supervisor).
#include "io/json_fields.h"

#include <gtest/gtest.h>

namespace fleetloc::io {
namespace {

TEST(DumpJson, InvalidUtf8IsReplacedNotThrown) {
  const nlohmann::json body{{"error", std::string("vehicle id 'agv-\xff\xfe' is not valid")}};
  EXPECT_THROW((void)body.dump(), nlohmann::json::type_error);  // what it guards against
  const std::string text = DumpJson(body);
  EXPECT_NE(text.find("agv-\xef\xbf\xbd"), std::string::npos) << text;  // U+FFFD
  EXPECT_EQ(nlohmann::json::parse(text)["error"].get<std::string>().substr(0, 12), "vehicle id '");
  EXPECT_EQ(DumpJson({{"a", 1}}, 2), "{\n  \"a\": 1\n}");
}

TEST(JsonFields, RejectUnknownNamesTheFirstUnknownKeyAndListsTheKnownOnes) {
  const nlohmann::json object = {{"mount", {{"x", 1}, {"yaw", 0}, {"z", 2}}}};
  const JsonFields root(object, "cam.json");
  EXPECT_TRUE(root.RejectUnknown({"mount"}).ok());
  Result<JsonFields> mount = root.Object("mount");
  ASSERT_TRUE(mount.ok());
  EXPECT_EQ(mount->RejectUnknown({"x", "y", "yaw"}).message(),
            "cam.json: field 'mount.z': unknown key (known: x, y, yaw)");
  EXPECT_EQ(mount->RejectUnknown({"x", "y", "yaw"}).code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace fleetloc::io
