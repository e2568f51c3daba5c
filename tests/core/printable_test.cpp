// printable(): text from a file, safe to print.

#include "sets/core/printable.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using sets::printable;

TEST(Printable, EscapesControlBytesAndKeepsPrintableUtf8) {
  EXPECT_EQ(printable("\x1b[31mred"), "\\x1b[31mred");
  EXPECT_EQ(printable("a\nb\tc\rd"), "a\\nb\\tc\\rd");
  EXPECT_EQ(printable(std::string("nul\0byte", 8)), "nul\\x00byte");
  EXPECT_EQ(printable("del\x7f"), "del\\x7f");
  EXPECT_EQ(printable("temp\xc3\xa9rature \xe2\x84\x83"), "temp\xc3\xa9rature \xe2\x84\x83");  // é, ℃
  EXPECT_EQ(printable("\xc2\x9b" "2J"), "\\xc2\\x9b2J");        // C1 control CSI in UTF-8
  EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");                // not UTF-8
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");                // overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");       // surrogate
  EXPECT_EQ(printable("\xe2\x82"), "\\xe2\\x82");                // truncated sequence
  EXPECT_EQ(printable("abcdef", 3), "abc...");
}

RC_GTEST_PROP(Printable, OutputHasNoControlBytesAndPrintableInputIsKept, (const std::string& s)) {
  const std::string out = printable(s, s.size());
  for (unsigned char c : out) RC_ASSERT(c >= 0x20 && c != 0x7F);
  bool plain = true;
  for (unsigned char c : s) plain = plain && c >= 0x20 && c < 0x7F;
  if (plain) RC_ASSERT(out == s);
}
