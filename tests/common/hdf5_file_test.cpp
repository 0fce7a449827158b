// String attributes read the same whether stored with a fixed length (as pilelab writes them)
// or a variable length (as h5py writes a Python str, e.g. when a user edits a file).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>

#include "common/hdf5_file.h"

using pilelab::H5File;

TEST(H5File, StringAttributesOfFixedAndVariableLength) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("pilelab_h5_strings_" + std::to_string(::getpid()) + ".h5")).string();
  {
    H5File f = H5File::create(path);
    f.set_attribute("/", "fixed", std::string("pilelab-dem"));
    f.close();
  }
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, "variable", type, space, H5P_DEFAULT, H5P_DEFAULT);
    const char* text = "edited with h5py";
    EXPECT_GE(H5Awrite(a, type, &text), 0);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
    H5Fclose(f);
  }
  const H5File f = H5File::open_read(path);
  EXPECT_EQ(f.attribute_string("/", "fixed"), "pilelab-dem");
  EXPECT_EQ(f.attribute_string("/", "variable"), "edited with h5py");
  std::filesystem::remove(path);
}

// A dataset in the way of a path is named in the error, rather than the group behind it that
// could not be created.
TEST(H5File, ADatasetWhereAGroupMustGoIsNamed) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("pilelab_h5_in_the_way_" + std::to_string(::getpid()) + ".h5")).string();
  H5File f = H5File::create(path);
  f.write("/snapshots/settled", std::vector<double>{1.0, 2.0});
  try {
    f.write("/snapshots/settled/x", std::vector<double>{3.0});
    ADD_FAILURE() << "writing below a dataset was accepted";
  } catch (const std::exception& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("/snapshots/settled exists and is not a group"), std::string::npos) << message;
  }
  f.write("/snapshots/relaxed/x", std::vector<double>{4.0});  // an existing group still takes new members
  EXPECT_EQ(f.read_doubles("/snapshots/relaxed/x"), std::vector<double>{4.0});
  f.close();
  std::filesystem::remove(path);
}
