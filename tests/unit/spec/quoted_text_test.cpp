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

// Valid UTF-8 that would change how the line reads: C1 controls, line separators and the
// bidirectional controls are shown as \u escapes; other characters beside them stay as sent.
TEST(QuotedText, InvisibleAndReorderingCharactersAreEscaped) {
  EXPECT_EQ(quoted_text("a\xc2\x85"
                        "b\xc2\x9b"),
            "\"a\\u0085b\\u009b\"");  // NEL, CSI
  EXPECT_EQ(quoted_text("x\xe2\x80\xae"
                        "evil"),
            "\"x\\u202eevil\"");  // right-to-left override
  EXPECT_EQ(quoted_text("\xe2\x81\xa6\xe2\x81\xa9"), "\"\\u2066\\u2069\"");  // isolates
  EXPECT_EQ(quoted_text("\xe2\x80\xa8\xe2\x80\x8f\xd8\x9c"), "\"\\u2028\\u200f\\u061c\"");
  // Their neighbours are ordinary text: U+00A0, U+2030 (per mille), U+2065 (unassigned).
  EXPECT_EQ(quoted_text("\xc2\xa0\xe2\x80\xb0\xe2\x81\xa5"),
            "\"\xc2\xa0\xe2\x80\xb0\xe2\x81\xa5\"");
  // The cut counts the bytes sent, not the escape's.
  const std::string overrides = [] {
    std::string s;
    for (int i = 0; i < 30; ++i) s += "\xe2\x80\xae";
    return s;
  }();
  std::string shown;
  for (int i = 0; i < 21; ++i) shown += "\\u202e";
  EXPECT_EQ(escaped_text(overrides), shown + "\xe2\x80\xa6 (90 bytes)");
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
