// The prerequisite guard itself (test_support/prerequisites.h): under CI=true a missing
// prerequisite must fail the test, never skip it, or CI could pass by skipping.
#include <cstdlib>
#include <optional>
#include <string>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "test_support/prerequisites.h"

namespace {

// Sets CI for the scope and puts back what was there.
class ScopedCi {
 public:
  explicit ScopedCi(const char* value) {
    if (const char* old = std::getenv("CI")) old_ = old;
    if (value != nullptr)
      setenv("CI", value, 1);
    else
      unsetenv("CI");
  }
  ~ScopedCi() {
    if (old_)
      setenv("CI", old_->c_str(), 1);
    else
      unsetenv("CI");
  }
  ScopedCi(const ScopedCi&) = delete;
  ScopedCi& operator=(const ScopedCi&) = delete;

 private:
  std::optional<std::string> old_;
};

void require_missing_program() {
  ILLUM_REQUIRE_PROGRAM("illum-no-such-program-anywhere");
}

}  // namespace

TEST(Prerequisites, CiIsRecognised) {
  {
    ScopedCi ci("true");
    EXPECT_TRUE(illum::test::in_ci());
  }
  {
    ScopedCi ci("1");
    EXPECT_TRUE(illum::test::in_ci());
  }
  {
    ScopedCi ci("false");
    EXPECT_FALSE(illum::test::in_ci());
  }
  {
    ScopedCi ci(nullptr);
    EXPECT_FALSE(illum::test::in_ci());
  }
}

TEST(Prerequisites, MissingProgramFailsUnderCi) {
  ScopedCi ci("true");
  EXPECT_FATAL_FAILURE(require_missing_program(),
                       "CI=true but program 'illum-no-such-program-anywhere' on PATH");
}

TEST(Prerequisites, PresentProgramPasses) {
  ScopedCi ci("true");
  ILLUM_REQUIRE_PROGRAM("sh");  // POSIX: always on PATH where the tests run
  SUCCEED();
}
