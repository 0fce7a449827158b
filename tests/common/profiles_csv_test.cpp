// profiles.csv is shared: each stage replaces its own sources' rows and keeps the rest.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/profiles_csv.h"

using namespace pilelab;

namespace {
std::string temp_csv(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (name + std::to_string(::getpid()) + ".csv")).string();
}
}  // namespace

TEST(ProfilesCsv, StagesReplaceOnlyTheirOwnRows) {
  const std::string path = temp_csv("profiles");
  std::filesystem::remove(path);
  write_profile_values(path, {{"dem", "sigma_yy", 0.0, -0.1, 0.8, 0.05, true}, {"dem", "sigma_yy", 0.0, 0.1, 0.7, 0.04, true}});
  write_profile_values(path, {{"fpa", "sigma_yy", 0.0, 0.0, 0.6, 0.0, false}});
  write_profile_values(path, {{"dem", "sigma_yy", 0.0, 0.0, 0.9, 0.01, true}});
  const auto rows = read_profile_values(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].source, "fpa");
  EXPECT_FALSE(rows[0].has_stderr);
  EXPECT_EQ(rows[1].source, "dem");
  EXPECT_EQ(rows[1].value, 0.9);
  EXPECT_EQ(rows[1].stderr_, 0.01);
  std::filesystem::remove(path);
}

TEST(ProfilesCsv, MalformedLineIsNamed) {
  const std::string path = temp_csv("bad");
  std::ofstream(path) << "source,quantity,y_over_h,x_m,value,stderr\ndem,sigma_yy,0,abc,1,\n";
  try {
    read_profile_values(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(ProfilesCsv, PointsAreCellCentred) {
  const auto x = profile_points(-1.0, 1.0, 4);
  ASSERT_EQ(x.size(), 4u);
  EXPECT_DOUBLE_EQ(x[0], -0.75);
  EXPECT_DOUBLE_EQ(x[3], 0.75);
}
