#include "access_tokens.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace soltex::server {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_access_tokens(text, "tokens.txt");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(AccessTokens, TheOldFileOfOneTokenIsOneUnnamedToken) {
  const auto tokens = parse_access_tokens("  s3cret-token \n", "f");
  ASSERT_EQ(tokens.size(), 1u);
  EXPECT_EQ(tokens[0].name, "");
  EXPECT_EQ(tokens[0].secret, "s3cret-token");
}

TEST(AccessTokens, NamedTokensCommentsAndBlankLines) {
  const auto tokens = parse_access_tokens(
      "# viewers\n"
      "alice\tAAAA\n"
      "\n"
      "bob   BBBB\r\n"
      "bob BBBB-next   \n"  // rotation: two tokens of one client
      "CCCC\n",
      "f");
  ASSERT_EQ(tokens.size(), 4u);
  EXPECT_EQ(tokens[0].name, "alice");
  EXPECT_EQ(tokens[0].secret, "AAAA");
  EXPECT_EQ(tokens[1].name, "bob");
  EXPECT_EQ(tokens[1].secret, "BBBB");
  EXPECT_EQ(tokens[2].secret, "BBBB-next");
  EXPECT_EQ(tokens[3].name, "");
}

TEST(AccessTokens, MistakesNameTheFileTheLineAndTheRule) {
  EXPECT_EQ(error_of("alice AAAA extra\n"),
            "tokens.txt line 1: expected 'NAME TOKEN' or 'TOKEN', found 3 fields");
  EXPECT_NE(error_of("# c\nal/ice AAAA\n").find("line 2: token name 'al/ice' must be"),
            std::string::npos);
  EXPECT_EQ(error_of("alice AAAA\n# c\nbob AAAA\n"),
            "tokens.txt line 3: the same token as line 1 (again as 'bob')");
  EXPECT_EQ(error_of("# nothing\n\n"), "tokens.txt: holds no token");
  EXPECT_NE(error_of("a " + std::string(5000, 'x')).find("at most 4096"), std::string::npos);
}

}  // namespace
}  // namespace soltex::server
