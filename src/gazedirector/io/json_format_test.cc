#include "gazedirector/io/json_format.h"

#include <gtest/gtest.h>

namespace gazedirector {
namespace {

TEST(JsonFormatTest, ErrorTextDropsTheLibrarysTag) {
  try {
    static_cast<void>(nlohmann::json::parse("{x"));
    FAIL() << "parsed";
  } catch (const nlohmann::json::exception& e) {
    EXPECT_EQ(std::string(e.what()).rfind("[json.exception.parse_error.101] ", 0), 0u) << e.what();
    EXPECT_EQ(JsonErrorText(e).rfind("parse error at line 1, column 2: ", 0), 0u) << JsonErrorText(e);
  }
  try {
    static_cast<void>(nlohmann::json::parse("[1]").at(3));
    FAIL() << "read past the end";
  } catch (const nlohmann::json::exception& e) {
    EXPECT_EQ(JsonErrorText(e), "array index 3 is out of range");
  }
}

}  // namespace
}  // namespace gazedirector
