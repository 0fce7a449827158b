// H5File: string attributes of either length, datasets in the way named, and checksummed data
// (a flipped bit refused).
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include "common/hdf5_file.h"

using pilelab::H5File;

// String attributes read the same whether stored with a fixed length (as pilelab writes them)
// or a variable length (as h5py writes a Python str, e.g. when a user edits a file).
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

// A flipped bit in a dataset's data is a read error naming the file and the dataset, never a
// silently different value: every dataset carries a Fletcher-32 checksum (issue 58 point 12).
// The flip goes into the stored bytes of a value the test can find: a known pattern of doubles,
// large enough to span several chunks.
TEST(H5File, AFlippedBitInADatasetIsRefused) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("pilelab_h5_flip_" + std::to_string(::getpid()) + ".h5")).string();
  const std::vector<double> values(300000, 0.1234567890123);
  const std::vector<std::int64_t> indices(1000, 0x0123456789ABCDEF);
  {
    H5File f = H5File::create(path);
    f.write("/snapshots/settled/position", values, {values.size() / 2, 2}, "m");
    f.write("/snapshots/settled/body", indices);
    f.close();
  }
  EXPECT_EQ(H5File::open_read(path).read_doubles("/snapshots/settled/position"), values);
  for (const auto& [dataset, pattern] :
       {std::pair<std::string, std::string>{"/snapshots/settled/position", std::string(reinterpret_cast<const char*>(values.data()), 8)},
        {"/snapshots/settled/body", std::string(reinterpret_cast<const char*>(indices.data()), 8)}}) {
    const std::string copy = path + ".flipped.h5";
    std::filesystem::copy_file(path, copy, std::filesystem::copy_options::overwrite_existing);
    std::string bytes;
    {
      std::ifstream in(copy, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::size_t at = bytes.find(pattern);
    ASSERT_NE(at, std::string::npos) << dataset;
    bytes[at + 3] ^= 0x10;  // one bit of the first value
    std::ofstream(copy, std::ios::binary | std::ios::trunc) << bytes;
    try {
      if (dataset.find("body") != std::string::npos)
        H5File::open_read(copy).read_ints(dataset);
      else
        H5File::open_read(copy).read_doubles(dataset);
      ADD_FAILURE() << dataset << ": a flipped bit was read silently";
    } catch (const std::exception& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(copy), std::string::npos) << message;
      EXPECT_NE(message.find(dataset + ": "), std::string::npos) << message;
      EXPECT_NE(message.find("checksum"), std::string::npos) << message;
    }
    std::filesystem::remove(copy);
  }
  std::filesystem::remove(path);
}
