#include "soltex/common/quoted_text.h"

#include <gtest/gtest.h>

#include <string>

namespace soltex {
namespace {

using namespace std::string_literals;

TEST(QuotedText, ShortTextIsQuotedUnchanged) {
  EXPECT_EQ(quoted_text("noise3d"), "\"noise3d\"");
  EXPECT_EQ(quoted_text(""), "\"\"");
  EXPECT_EQ(quoted_text("\xd1\x8f\xd1\x8f"), "\"\xd1\x8f\xd1\x8f\"");  // UTF-8 stays as is
  EXPECT_EQ(escaped_text("p3"), "p3");
}

TEST(QuotedText, LongTextIsCutWithItsLength) {
  const std::string shown = quoted_text(std::string(10000, 'a'));
  EXPECT_EQ(shown, "\"" + std::string(kQuotedTextBytes, 'a') + "\xe2\x80\xa6\" (10000 bytes)");
  EXPECT_EQ(escaped_text(std::string(100000, 'b')),
            std::string(kQuotedTextBytes, 'b') + "\xe2\x80\xa6 (100000 bytes)");
  // A name as long as the limits allow is shown whole.
  EXPECT_EQ(quoted_text(std::string(kQuotedTextBytes, 'c')),
            "\"" + std::string(kQuotedTextBytes, 'c') + "\"");
}

TEST(QuotedText, CutNeverSplitsACharacter) {
  std::string cyrillic = "a";
  for (int i = 0; i < 40; ++i) cyrillic += "\xd1\x8f";  // 81 bytes: byte 64 is mid-letter
  std::string kept = "a";
  for (int i = 0; i < 31; ++i) kept += "\xd1\x8f";
  EXPECT_EQ(escaped_text(cyrillic), kept + "\xe2\x80\xa6 (81 bytes)");
}

TEST(QuotedText, NulAndControlCharactersAreEscaped) {
  EXPECT_EQ(quoted_text("a\0b"s), "\"a\\x00b\"");
  EXPECT_EQ(quoted_text("line\nnext\r\tend\x7f"), "\"line\\nnext\\r\\tend\\x7f\"");
  EXPECT_EQ(quoted_text("say \"hi\" \\o/"), "\"say \\\"hi\\\" \\\\o/\"");
}

TEST(QuotedText, BytesThatAreNotUtf8AreEscaped) {
  EXPECT_EQ(quoted_text("\xff\xfe"), "\"\\xff\\xfe\"");
  EXPECT_EQ(quoted_text("a\xc0\xaf"), "\"a\\xc0\\xaf\"");               // overlong '/'
  EXPECT_EQ(quoted_text("\xed\xa0\x80"), "\"\\xed\\xa0\\x80\"");        // a surrogate
  EXPECT_EQ(quoted_text("\xe2\x82"), "\"\\xe2\\x82\"");                 // cut short
  EXPECT_EQ(quoted_text("\xe2\x82\xac\xe2"), "\"\xe2\x82\xac\\xe2\"");  // euro, then a stray lead
}

TEST(QuotedText, EscapedTextStaysBoundedWhateverIsSent) {
  const std::string shown = quoted_text(std::string(100000, '\0'));
  EXPECT_LE(shown.size(), 4 * kQuotedTextBytes + 32) << shown;
  EXPECT_NE(shown.find("(100000 bytes)"), std::string::npos);
}

}  // namespace
}  // namespace soltex
