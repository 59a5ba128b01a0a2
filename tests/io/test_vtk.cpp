// The .vtu writer: integer arrays stay integers however large (as text; tools/post/check_vtu.py
// reads all three formats with VTK).
#include <gtest/gtest.h>

#include <string>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/io/vtk.hpp"
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
