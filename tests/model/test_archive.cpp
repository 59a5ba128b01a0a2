// The checkpoint's archive: one function writes and reads back, every kind of data the same bits;
// a short or foreign archive is refused, not read as something else.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "tetcontact/model/persist.hpp"

using namespace tc;

namespace {

struct Plain {
  using archive_bitwise = void;
  int a;
  Vec3 v;
};

}  // namespace

TEST(Archive, WhatIsWrittenIsReadBackBitForBit) {
  std::vector<double> d{0.1, -0.0, std::numeric_limits<double>::denorm_min(),
                        std::numeric_limits<double>::quiet_NaN(), 1e300};
  std::vector<Vec3> vs{Vec3(1, 2, 3), Vec3(-4, 5e-300, 6)};
  std::vector<std::vector<Index>> nested{{1, 2, 3}, {}, {7}};
  std::vector<std::pair<std::string, double>> named{{"elements", 1.5}, {"", 2.5}};
  std::optional<std::string> some = "x", none;
  std::vector<Plain> plain{{3, Vec3(7, 8, 9)}};
  std::vector<bool> bits{true, false, true};
  Sample s;
  s.step = 12;
  s.momentum = Vec3(1, -1, 0.5);
  s.wall_force = {3.0, 4.0};
  s.final = true;
  Archive out;
  out.section("first");
  out(d, vs, nested, named, some, none, plain, bits, s);
  Archive in(out.bytes());
  std::vector<double> d2;
  std::vector<Vec3> vs2;
  std::vector<std::vector<Index>> nested2;
  std::vector<std::pair<std::string, double>> named2;
  std::optional<std::string> some2, none2 = "y";
  std::vector<Plain> plain2;
  std::vector<bool> bits2;
  Sample s2;
  in.section("first");
  in(d2, vs2, nested2, named2, some2, none2, plain2, bits2, s2);
  EXPECT_TRUE(in.at_end());
  ASSERT_EQ(d2.size(), d.size());
  for (std::size_t i = 0; i < d.size(); ++i)
    EXPECT_EQ(std::memcmp(&d[i], &d2[i], sizeof(double)), 0) << i;  // -0.0 and NaN too
  EXPECT_EQ(vs2, vs);
  EXPECT_EQ(nested2, nested);
  EXPECT_EQ(named2, named);
  EXPECT_EQ(some2, some);
  EXPECT_FALSE(none2.has_value());
  ASSERT_EQ(plain2.size(), 1u);
  EXPECT_EQ(plain2[0].a, 3);
  EXPECT_EQ(plain2[0].v, Vec3(7, 8, 9));
  EXPECT_EQ(bits2, bits);
  EXPECT_EQ(s2.step, 12);
  EXPECT_EQ(s2.momentum, s.momentum);
  EXPECT_EQ(s2.wall_force, s.wall_force);
  EXPECT_TRUE(s2.final);
}

TEST(Archive, AShortOrForeignArchiveIsRefused) {
  Archive out;
  out.section("state");
  std::vector<double> d(100, 1.0);
  out(d);
  const std::string bytes = out.bytes();
  // Cut anywhere: an error, never a shorter list.
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, bytes.size() / 2, bytes.size() - 1}) {
    Archive in(bytes.substr(0, cut));
    std::vector<double> back;
    EXPECT_THROW(
        {
          in.section("state");
          in(back);
        },
        ArchiveError)
        << cut;
  }
  // Another section where this one is expected: named both.
  Archive in(bytes);
  try {
    in.section("contact");
    FAIL() << "read another section";
  } catch (const ArchiveError& e) {
    EXPECT_NE(std::string(e.what()).find("'contact' expected, 'state' found"), std::string::npos)
        << e.what();
  }
}
