// export's frame selection and the VTK XML it writes, by hand.
#include <granstack/formats/vtk.hpp>
#include <granstack/postproc/export.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

using namespace granstack;

namespace {

std::vector<long> picked(const std::string& selection, long count) {
  const auto p = postproc::select_frames(selection, count);
  std::vector<long> out;
  for (long k = 0; k < count; ++k) {
    if (p[static_cast<std::size_t>(k)]) out.push_back(k);
  }
  return out;
}

TEST(ExportFrames, SelectionsPickTheFramesPythonSlicesWould) {
  EXPECT_EQ(picked("all", 4), (std::vector<long>{0, 1, 2, 3}));
  EXPECT_EQ(picked("0,-1", 5), (std::vector<long>{0, 4}));
  EXPECT_EQ(picked("::3", 10), (std::vector<long>{0, 3, 6, 9}));
  EXPECT_EQ(picked("-3:", 10), (std::vector<long>{7, 8, 9}));
  EXPECT_EQ(picked("2:5,8", 10), (std::vector<long>{2, 3, 4, 8}));
  EXPECT_EQ(picked("1:100:4", 10), (std::vector<long>{1, 5, 9}));  // an end past the last is the last
  EXPECT_THROW(picked("5:2", 10), std::invalid_argument);  // unlike Python's empty slice: a mistake, refused
}

TEST(ExportFrames, BadSelectionsAreRefusedWithTheFix) {
  for (const char* bad : {"", "x", "1:x", "::0", "::-2", "10", "-11", "1,,2", "1:2:3:4"}) {
    try {
      postproc::select_frames(bad, 10);
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'::10' (every tenth"), std::string::npos) << bad << ": " << e.what();
    }
  }
}

// The appended block: each array's 8-byte size, then its raw values, at the offsets the XML says.
TEST(Vtk, ArraysAreStoredRawAtTheirOffsets) {
  formats::VtkPoints p;
  p.xyz = {1.0, 2.0, 3.0, -0.0, 1e-300, 0.1};
  p.arrays.push_back({"id", 1, {}, {7, 8}});
  p.arrays.push_back({"v", 3, {0.5, -1.5, 2.5, 3.5, 4.5, 5.5}, {}});
  const std::string doc = formats::vtp_document(p);
  const std::size_t data = doc.find("encoding=\"raw\">\n   _") + std::strlen("encoding=\"raw\">\n   _");
  ASSERT_NE(doc.find("NumberOfPoints=\"2\" NumberOfVerts=\"2\""), std::string::npos) << doc;
  const auto offset = [&](const std::string& name) {
    const std::size_t at = doc.find("Name=\"" + name + "\"");
    const std::size_t o = doc.find("offset=\"", at) + 8;
    return std::stoul(doc.substr(o, doc.find('"', o) - o));
  };
  const auto value = [&](std::size_t at) {
    double d;
    std::memcpy(&d, doc.data() + data + at, sizeof d);
    return d;
  };
  std::uint64_t bytes;
  std::memcpy(&bytes, doc.data() + data + offset("Points"), sizeof bytes);
  EXPECT_EQ(bytes, 6 * sizeof(double));
  EXPECT_EQ(value(offset("Points") + 8 + 3 * 8), -0.0);
  EXPECT_TRUE(std::signbit(value(offset("Points") + 8 + 3 * 8)));
  EXPECT_EQ(value(offset("Points") + 8 + 4 * 8), 1e-300);
  EXPECT_EQ(value(offset("v") + 8 + 5 * 8), 5.5);
  std::int64_t id;
  std::memcpy(&id, doc.data() + data + offset("id") + 8 + 8, sizeof id);
  EXPECT_EQ(id, 8);
  EXPECT_THROW(formats::vtp_document({{1.0, 2.0, 3.0}, {{"bad", 3, {1.0}, {}}}, "", ""}), std::invalid_argument);
}

}  // namespace
