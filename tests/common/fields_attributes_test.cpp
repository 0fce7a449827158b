// The root attributes of fields.h5, as coarse/ writes them and every later stage reads them:
// what is written is read back exactly; a user's file without them reads the documented
// defaults; a non-finite number is refused, naming the file and the attribute.
#include "common/fields_attributes.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "common/error.h"

using namespace pilelab;

namespace {
std::string temp_h5(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string(name) + std::to_string(::getpid()) + ".h5")).string();
}
}  // namespace

TEST(FieldsAttributes, WhatIsWrittenIsReadBack) {
  const std::string path = temp_h5("pilelab_fields_attributes_");
  FieldsAttributes a;
  a.method = "gaussian";
  a.rve_radius_m = 0.0421;
  a.kernel_width_m = 0.0421;
  a.piles = 14;
  a.strain_to = "relaxed";
  a.gravity_change = -0.1;
  a.height_m = 0.334;
  a.rho_bulk_kg_per_m2 = 4159.5;
  a.gravity_m_per_s2 = 9.81;
  {
    H5File f = H5File::create(path);
    write_fields_attributes(f, a);
  }
  const FieldsAttributes b = read_fields_attributes(path);
  EXPECT_EQ(b.to_json(), a.to_json());
  EXPECT_DOUBLE_EQ(b.rho_g(), 4159.5 * 9.81);
  std::filesystem::remove(path);
}

TEST(FieldsAttributes, AFileWithoutThemReadsTheDefaults) {
  const std::string path = temp_h5("pilelab_fields_attributes_none_");
  { H5File f = H5File::create(path); }
  EXPECT_EQ(read_fields_attributes(path).to_json(), FieldsAttributes().to_json());
  std::filesystem::remove(path);
}

TEST(FieldsAttributes, ANonFiniteNumberIsRefusedWithItsName) {
  const std::string path = temp_h5("pilelab_fields_attributes_nan_");
  {
    H5File f = H5File::create(path);
    f.set_attribute("/", "rho_bulk_kg_per_m2", std::nan(""));
  }
  try {
    read_fields_attributes(path);
    FAIL() << "a NaN density was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rho_bulk_kg_per_m2"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}
