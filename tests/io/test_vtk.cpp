// The .vtu writer: integer arrays stay integers however large (as text); a compressed array is
// VTK's blocks, each the binary array's bytes (tools/post/check_vtu.py reads all three formats
// with VTK).
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/io/vtk.hpp"
#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

// 27,000 tets: offsets reach 108,000 and pass 100,000, whose shortest double form "1e+05"
// VTK's integer reader cannot read (regression: the cylinders case opened with no cells).
TEST(Vtu, IntegerArraysAreWrittenAsIntegers) {
  Model model = test::single_body_model(make_box(Vec3(0.3, 0.3, 0.4), {15, 15, 20}, HexSplit::six),
                                        test::aluminium());
  ASSERT_EQ(model.mesh.tets.size(), 27000u);
  const State st = initial_state(model);
  const std::string vtu = vtu_frame(model, st, {"body"}, {}, VtuFormat::ascii);
  EXPECT_NE(vtu.find("\n          100000\n"), std::string::npos);  // an offset
  EXPECT_NE(vtu.find("\n          108000\n"), std::string::npos);  // the last offset
  // No exponent or decimal point in any integer array.
  int arrays = 0;
  for (std::size_t at = vtu.find("<DataArray type=\""); at != std::string::npos;
       at = vtu.find("<DataArray type=\"", at + 1)) {
    const std::string type = vtu.substr(at + 17, vtu.find('"', at + 17) - at - 17);
    if (type != "Int32" && type != "Int64" && type != "UInt8") continue;
    ++arrays;
    const std::size_t open = vtu.find('>', at) + 1, close = vtu.find("</DataArray>", open);
    EXPECT_EQ(vtu.substr(open, close - open).find_first_of("e.+"), std::string::npos) << type;
  }
  EXPECT_GE(arrays, 4);  // body (points, cells), connectivity, offsets, types
}

namespace {

std::uint64_t u64_at(const std::string& s, std::size_t at) {
  std::uint64_t v = 0;
  std::memcpy(&v, s.data() + at, sizeof v);
  return v;
}

// The appended arrays of a binary or compressed frame, in their order: their offsets from the
// DataArray declarations, from the '_' that starts the appended section.
std::vector<std::size_t> appended_offsets(const std::string& vtu, std::size_t& start) {
  std::vector<std::size_t> offsets;
  for (std::size_t at = vtu.find("offset=\""); at != std::string::npos;
       at = vtu.find("offset=\"", at + 1))
    offsets.push_back(std::stoull(vtu.substr(at + 8, vtu.find('"', at + 8) - at - 8)));
  start = vtu.find("<AppendedData encoding=\"raw\">");
  start = vtu.find('_', start) + 1;
  return offsets;
}

}  // namespace

// Compressed frames: each array is VTK's blocks (a header of block count, block size, the last
// block's size where shorter, each block's compressed size), every block inflates to its
// stated size, and the blocks joined are the binary frame's bytes of that array, array by
// array; arrays past a block's size take several blocks; the file is byte for byte the same on
// one thread and on two.
TEST(Vtu, CompressedArraysAreVtksBlocksOfTheBinaryBytes) {
  Model model = test::single_body_model(make_box(Vec3(0.3, 0.3, 0.4), {15, 15, 20}, HexSplit::six),
                                        test::aluminium());
  State st = initial_state(model);
  for (std::size_t i = 0; i < st.x.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      st.x[i][d] += 1e-4 * std::sin(0.37 * static_cast<double>(3 * i + d));
      st.v[i][d] = 10.0 * std::cos(0.11 * static_cast<double>(3 * i + d));
    }
  for (std::size_t t = 0; t < st.p.size(); ++t) st.p[t] = 1e6 * std::sin(0.013 * t);
  const std::vector<std::string> fields = {"displacement", "velocity", "stress", "pressure",
                                           "body"};
  const int saved = parallel::threads();
  parallel::set_threads(1);
  const std::string one = vtu_frame(model, st, fields, {}, VtuFormat::compressed);
  parallel::set_threads(2);
  const std::string zipped = vtu_frame(model, st, fields, {}, VtuFormat::compressed);
  const std::string binary = vtu_frame(model, st, fields, {}, VtuFormat::binary);
  parallel::set_threads(saved);
  EXPECT_TRUE(one == zipped);

  std::size_t zstart = 0, bstart = 0;
  const std::vector<std::size_t> zoff = appended_offsets(zipped, zstart);
  const std::vector<std::size_t> boff = appended_offsets(binary, bstart);
  ASSERT_EQ(zoff.size(), boff.size());
  ASSERT_GE(zoff.size(), 8u);
  std::size_t most_blocks = 0;
  for (std::size_t a = 0; a < zoff.size(); ++a) {
    const std::size_t b = bstart + boff[a];
    const std::string bytes = binary.substr(b + 8, u64_at(binary, b));
    std::size_t z = zstart + zoff[a];
    const std::uint64_t blocks = u64_at(zipped, z), block = u64_at(zipped, z + 8),
                        last = u64_at(zipped, z + 16);
    most_blocks = std::max<std::size_t>(most_blocks, blocks);
    std::size_t data = z + 24 + 8 * blocks;
    std::string joined;
    for (std::uint64_t k = 0; k < blocks; ++k) {
      const std::uint64_t packed = u64_at(zipped, z + 24 + 8 * k);
      const std::uint64_t expected = k + 1 == blocks && last != 0 ? last : block;
      std::string out(expected + 16, '\0');
      uLongf size = out.size();
      ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &size,
                           reinterpret_cast<const Bytef*>(zipped.data() + data), packed),
                Z_OK)
          << "array " << a << ", block " << k;
      ASSERT_EQ(size, expected) << "array " << a << ", block " << k;
      joined.append(out.data(), size);
      data += packed;
    }
    EXPECT_TRUE(joined == bytes) << "array " << a << ": " << joined.size() << " bytes against "
                                 << bytes.size();
  }
  EXPECT_GT(most_blocks, 1u);  // the connectivity's 864,000 bytes
}
