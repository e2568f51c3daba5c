// Recordings from MATLAB .mat files (src/data/mat_file.cpp through read_mat), hostile ones
// included. Sizes in a .mat file are checked against the bytes really there before anything is
// allocated; every error is an InputError naming the file and the byte offset or variable; bytes of
// the file are escaped in messages.

#include <gtest/gtest.h>
#include <unistd.h>
#include <matio.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "sets/core/error.hpp"
#include "data/mat_file.hpp"
#include "sets/data/recording.hpp"
#include "support/messages.hpp"
#include "support/shared_data.hpp"

using namespace sets;
using sets::test::contains;
using sets::test::input_error_of;

namespace {

// ---- a little writer of level 5 files (little endian), as in tests/fuzz/make_mat_seeds.py
std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }
std::string pad8(std::string b) { return b + std::string((8 - b.size() % 8) % 8, '\0'); }
std::string element(std::uint32_t type, const std::string& payload) { return u32(type) + u32(static_cast<std::uint32_t>(payload.size())) + pad8(payload); }
std::string doubles(const std::vector<double>& v) { return std::string(reinterpret_cast<const char*>(v.data()), 8 * v.size()); }
std::string matrix(const std::string& name, std::int32_t rows, std::int32_t cols, const std::string& real_part) {
  std::string body = element(6, u32(6) + u32(0));  // array flags: mxDOUBLE
  body += element(5, u32(static_cast<std::uint32_t>(rows)) + u32(static_cast<std::uint32_t>(cols)));
  body += element(1, name) + real_part;
  return u32(14) + u32(static_cast<std::uint32_t>(body.size())) + body;
}
std::string v5(const std::string& elements) {
  std::string header = "MATLAB 5.0 MAT-file, sets test";
  header.resize(116, ' ');
  header += std::string(8, '\0') + std::string("\x00\x01IM", 4);
  return header + elements;
}
std::string compressed(const std::string& element_bytes) {
  uLongf n = compressBound(element_bytes.size());
  std::string z(n, '\0');
  compress(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(element_bytes.data()), element_bytes.size());
  z.resize(n);
  return u32(15) + u32(static_cast<std::uint32_t>(n)) + z;
}

std::string temp_file(const std::string& bytes) {
  static int count = 0;
  const auto path = std::filesystem::temp_directory_path() /
                    ("sets_recording_test_" + std::to_string(::getpid()) + "_" + std::to_string(count++) + ".mat");
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

std::string mat_error(const std::string& bytes) {
  const std::string path = temp_file(bytes);
  const std::string m = input_error_of([&] { read_mat(path); });
  std::filesystem::remove(path);
  return m;
}

std::string seed(const std::string& name) { return std::string(SETS_SOURCE_DIR) + "/tests/fuzz/corpus/mat/" + name; }

}  // namespace
TEST(Recording, MatSeedsReadInBothByteOrdersCompressedOrNot) {
  for (const char* name : {"v5_le.mat", "v5_be.mat", "v5_le_compressed.mat", "v5_be_compressed.mat", "v4_le.mat", "v4_be.mat"}) {
    SCOPED_TRACE(name);
    const Recording r = read_mat(seed(name));
    ASSERT_EQ(r.rows(), 4);
    EXPECT_EQ(r.column("t"), (std::vector<double>{0.0, 0.1, 0.2, 0.3}));
    EXPECT_EQ(r.column("u"), (std::vector<double>{1, -2, 0, 3}));
    EXPECT_EQ(r.column("y"), (std::vector<double>{1, -2, 0.5, 3}));
    EXPECT_FALSE(r.has("gain"));  // a scalar
    EXPECT_FALSE(r.has("z"));     // complex
  }
  for (const char* name : {"v5_le_skipped.mat", "v5_be_skipped.mat"}) {  // matrix, complex, char, cell
    const Recording r = read_mat(seed(name));
    EXPECT_EQ(r.names, (std::vector<std::string>{"t", "u"})) << name;
  }
  for (const char* name : {"v5_le_integers.mat", "v5_be_integers.mat"}) {
    const Recording r = read_mat(seed(name));
    ASSERT_EQ(r.names.size(), 8u) << name;
    for (const auto& c : r.columns) EXPECT_EQ(c, (std::vector<double>{1, 2, 3})) << name;
  }
}

TEST(Recording, MatSizesAreCheckedAgainstTheFileBeforeAllocating) {
  const std::string data = element(9, doubles({1, 2, 3, 4}));
  // A 1 x 2^31-1 vector with 32 bytes of data: matio asked for 16 GB here.
  std::string m = mat_error(v5(matrix("x", 1, 0x7FFFFFFF, data)));
  EXPECT_TRUE(contains(m, "byte 160: variable \"x\" has more than 134217728 elements")) << m;
  m = mat_error(v5(matrix("x", 1, 100000000, data)));
  EXPECT_TRUE(contains(m, "variable \"x\" has 100000000 elements but its real part holds 32 bytes")) << m;
  m = mat_error(v5(matrix("x", -1, 4, data)));
  EXPECT_TRUE(contains(m, "negative dimension -1")) << m;
  // An element that claims more bytes than the file has.
  std::string truncated = v5(matrix("x", 1, 4, data));
  truncated.resize(truncated.size() - 9);
  m = mat_error(truncated);
  EXPECT_TRUE(contains(m, "byte 136: data element needs")) << m;
  // A compressed variable whose inner element claims 2 GB, and one whose stream is cut short.
  m = mat_error(v5(compressed(u32(14) + u32(0x80000000u) + std::string(64, '\0'))));
  EXPECT_TRUE(contains(m, "compressed variable at byte 128, inflated byte 0: the variable inflates to 2147483648 bytes")) << m;
  const std::string stream = compressed(matrix("x", 1, 4, data)).substr(8, 20);
  m = mat_error(v5(u32(15) + u32(20) + stream));
  EXPECT_TRUE(contains(m, "compressed variable at byte 128, inflated byte")) << m;
}

TEST(Recording, MatLevel4SizesAndUnknownFormats) {
  // Level 4: 2^30 x 2^30 doubles in a 40-byte file.
  std::string v4 = u32(0) + u32(1u << 30) + u32(1u << 30) + u32(0) + u32(2) + std::string("x\0", 2) + doubles({1, 2});
  std::string m = mat_error(v4);
  EXPECT_TRUE(contains(m, "variable \"x\" is 1073741824 x 1073741824 but the file has only 16 bytes left")) << m;
  EXPECT_TRUE(contains(mat_error("hello"), "not a MATLAB .mat file (too short)"));
  EXPECT_TRUE(contains(mat_error(std::string(300, '\x5a')), "byte 0: not a MATLAB .mat file"));
  std::string v73 = v5("");
  v73[124] = 0;
  v73[125] = 2;
  EXPECT_TRUE(contains(mat_error(v73 + std::string(600, '\0')), "a v7.3 .mat header but no HDF5 data at byte 512"));
}

TEST(Recording, MatNamesAndValuesInMessagesAreEscaped) {
  const std::string m = mat_error(v5(matrix("\x1b[2J", 1, 2, element(9, doubles({1, NAN})))));
  EXPECT_TRUE(contains(m, "variable \"\\x1b[2J\", sample 2: NaN or infinite value")) << m;
  EXPECT_FALSE(sets::test::has_raw_control_bytes(m)) << m;
}

TEST(Recording, MatFileHasTheSameRecordAsTheCsv) {
  const auto mat = test::shared_data("emps/DATA_EMPS.mat");
  const auto csv = test::shared_data("emps/estimation.csv");
  if (mat.empty() || csv.empty()) GTEST_SKIP() << "emps data not found under ../shared/data";
  const Recording m = read_mat(mat.string()), c = read_csv(csv.string());
  ASSERT_EQ(m.rows(), c.rows());
  const auto& vir = m.column("vir");
  const auto& u = c.column("u");
  for (int k = 0; k < m.rows(); k += 997) EXPECT_NEAR(vir[static_cast<std::size_t>(k)], u[static_cast<std::size_t>(k)], 1e-9);
}

namespace {

// Writes `vars` (name -> rows x cols doubles, column-major) and an int32 vector with matio in the
// given format; false if this matio cannot write that format.
bool write_with_matio(const std::string& path, mat_ft format, matio_compression compression) {
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, format);
  if (!mat) return false;
  bool ok = true;
  auto put = [&](const char* name, std::size_t rows, std::size_t cols, std::vector<double> values) {
    std::size_t dims[2] = {rows, cols};
    matvar_t* v = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, values.data(), 0);
    ok = ok && v && Mat_VarWrite(mat, v, compression) == 0;
    Mat_VarFree(v);
  };
  put("t", 1, 5, {0.0, 0.1, 0.2, 0.30000000000000004, 0.4});  // a row vector
  put("u", 5, 1, {1, -2, 1e-310, 3, -1e300});                   // a column; a subnormal; a large value
  put("gain", 1, 1, {2.5});                                      // a scalar: not a signal
  put("M", 2, 3, {1, 2, 3, 4, 5, 6});                            // a matrix: not a signal
  if (format != MAT_FT_MAT4) {
    std::int32_t counts[5] = {7, -8, 9, 0, 2147483647};
    std::size_t dims[2] = {5, 1};
    matvar_t* v = Mat_VarCreate("n", MAT_C_INT32, MAT_T_INT32, 2, dims, counts, 0);
    ok = ok && v && Mat_VarWrite(mat, v, compression) == 0;
    Mat_VarFree(v);
  }
  Mat_Close(mat);
  return ok;
}

}  // namespace

TEST(MatFile, VectorsWrittenByMatioReadBackExactlyInEveryFormat) {
  struct Case {
    const char* what;
    mat_ft format;
    matio_compression compression;
  };
  for (const Case& c : {Case{"v5", MAT_FT_MAT5, MAT_COMPRESSION_NONE}, Case{"v5 compressed", MAT_FT_MAT5, MAT_COMPRESSION_ZLIB},
                        Case{"v4", MAT_FT_MAT4, MAT_COMPRESSION_NONE}, Case{"v7.3", MAT_FT_MAT73, MAT_COMPRESSION_NONE}}) {
    SCOPED_TRACE(c.what);
    const std::string path = temp_file("");
    if (!write_with_matio(path, c.format, c.compression)) {
      std::filesystem::remove(path);
      if (c.format == MAT_FT_MAT73) continue;  // matio without HDF5 cannot write v7.3
      FAIL() << "matio could not write " << c.what;
    }
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const Mat_format expected = c.format == MAT_FT_MAT4 ? Mat_format::v4 : c.format == MAT_FT_MAT73 ? Mat_format::v73 : Mat_format::v5;
    EXPECT_EQ(mat_format(bytes), expected);
    const Recording r = read_mat(path);
    std::filesystem::remove(path);
    std::vector<std::string> names{"t", "u"};
    if (c.format != MAT_FT_MAT4) names.push_back("n");
    std::vector<std::string> got = r.names;
    if (c.format == MAT_FT_MAT73) {  // HDF5 lists the variables by name, not in writing order
      std::sort(got.begin(), got.end());
      std::sort(names.begin(), names.end());
    }
    EXPECT_EQ(got, names);  // file order; the scalar and the matrix are skipped
    ASSERT_EQ(r.rows(), 5);
    EXPECT_EQ(r.column("t"), (std::vector<double>{0.0, 0.1, 0.2, 0.30000000000000004, 0.4}));
    EXPECT_EQ(r.column("u"), (std::vector<double>{1, -2, 1e-310, 3, -1e300}));
    if (c.format != MAT_FT_MAT4) {
      EXPECT_EQ(r.column("n"), (std::vector<double>{7, -8, 9, 0, 2147483647}));
    }
  }
}

TEST(MatFile, ReadersOfTheBytesNameTheFileAndOffsetOfATruncatedElement) {
  const std::string path = temp_file("");
  ASSERT_TRUE(write_with_matio(path, MAT_FT_MAT5, MAT_COMPRESSION_NONE));
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  const auto vars = read_mat_v5_vectors(bytes, "x.mat");
  ASSERT_EQ(vars.size(), 3u);
  EXPECT_EQ(vars[0].name, "t");
  bytes.resize(bytes.size() - 3);  // the last element (the int32 vector) loses its end
  const std::string m = input_error_of([&] { read_mat_v5_vectors(bytes, "x.mat"); });
  EXPECT_TRUE(contains(m, "x.mat")) << m;
  EXPECT_TRUE(contains(m, "byte ")) << m;
}
