#include "app/progress_reporter.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace lancer {
namespace {

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

TEST(ProgressReporter, PlainLinePerTenPercentWhenNotATerminal) {
  std::ostringstream err;
  ProgressReporter p(err, false);
  for (std::size_t i = 1; i <= 257; ++i) p.update(i, 257);
  p.finish();
  const std::string s = err.str();
  EXPECT_EQ(count(s, "\n"), 10) << s;
  EXPECT_EQ(count(s, "\r"), 0);
  EXPECT_NE(s.find("progress:  10%"), std::string::npos) << s;
  EXPECT_NE(s.find("progress: 100%"), std::string::npos) << s;
}

TEST(ProgressReporter, BarWithPercentAndEtaOnATerminal) {
  std::ostringstream err;
  ProgressReporter p(err, true);
  p.update(1, 4);
  p.update(2, 4);
  p.update(4, 4);
  p.finish();
  const std::string s = err.str();
  EXPECT_EQ(count(s, "\r"), 3);
  EXPECT_NE(s.find(" 25.0%"), std::string::npos) << s;
  EXPECT_NE(s.find("100.0%"), std::string::npos) << s;
  EXPECT_NE(s.find("ETA"), std::string::npos);
  EXPECT_EQ(s.back(), '\n');  // the shell prompt starts on a fresh line
}

TEST(ProgressReporter, ZeroTotalPrintsNothing) {
  std::ostringstream err;
  ProgressReporter p(err, false);
  p.update(0, 0);
  EXPECT_TRUE(err.str().empty());
}

}  // namespace
}  // namespace lancer
