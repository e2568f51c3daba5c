// One mapping from an app-ending exception to the documented exit code (docs/contributing.md).

#include <gtest/gtest.h>

#include <filesystem>

#include "sets/core/error.hpp"
#include "sets/core/exit_code.hpp"

TEST(ExitCode, EachErrorKindMapsToItsDocumentedCode) {
  EXPECT_EQ(sets::exit_code_for(sets::InputError("x")), 1);
  EXPECT_EQ(sets::exit_code_for(sets::UnsupportedError("x")), 1);
  EXPECT_EQ(sets::exit_code_for(std::filesystem::filesystem_error("x", std::error_code())), 1);
  EXPECT_EQ(sets::exit_code_for(sets::EmptySetError("x")), 2);
  EXPECT_EQ(sets::exit_code_for(sets::NumericalError("x")), 3);
  testing::internal::CaptureStderr();
  const int code = sets::report_failure("sets-app", sets::NumericalError("LP failed"));
  EXPECT_EQ(code, 3);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "sets-app: numerical failure: LP failed\n");
}
