// The Dots CSV reader's own decimal parser (plain decimals of up to 15
// digits) must give exactly the double std::from_chars gives, for every
// spelling the simulator and cameras write, and send everything else down
// the checked path (exponents, long digit strings, bad text).
#include <gtest/gtest.h>

#include <charconv>
#include <cstdio>
#include <random>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/dots_csv.hpp"

using namespace earshot::tracker;

namespace {

/// A Dots line (no truth) with `v` as t (every field goes through the same
/// parser; pixels are range-checked after it).
std::string line_of(const std::string& v) { return v + ",1,2,3,4,5,6,7,8"; }

double from_chars(const std::string& v) {
  double out = 0.0;
  const char* first = v.data() + (v[0] == '+' ? 1 : 0);
  std::from_chars(first, v.data() + v.size(), out);
  return out;
}

}  // namespace

TEST(DotsNumberParsing, SameDoubleAsFromChars) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> digits(1, 18), point(0, 18), sign(0, 3);
  std::uniform_int_distribution<int> digit(0, 9);
  for (int i = 0; i < 20000; ++i) {
    std::string v = sign(rng) == 0 ? "-" : "";
    const int n = digits(rng), p = point(rng);
    for (int k = 0; k < n; ++k) {
      if (k == p && k > 0) v += '.';
      v += static_cast<char>('0' + digit(rng));
    }
    const DotFrame f = parse_dots_line(line_of(v), false, "test.csv", 2);
    const double want = from_chars(v);
    ASSERT_EQ(f.t, want) << v;  // bit for bit (both are correctly rounded)
  }
  for (const char* v : {"0", "-0", "5.", ".5", "0.01", "1099.831324", "-2.744931845e-05", "1e3", "+7.25",
                        "123456789012345", "1234567890123456", "0.000000000000000001"}) {
    const DotFrame f = parse_dots_line(line_of(v), false, "test.csv", 2);
    EXPECT_EQ(f.t, from_chars(v)) << v;
  }
}

TEST(DotsNumberParsing, BadTextStillNamesTheField) {
  for (const char* v : {"-", ".", "1.2.3", "12a", "--1", "nan"}) {
    try {
      (void)parse_dots_line(std::string(v) + ",1,1,1,1,1,1,1,1", false, "test.csv", 9);
      ADD_FAILURE() << v;
    } catch (const earshot::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("t_s"), std::string::npos) << e.what();
    }
  }
}
