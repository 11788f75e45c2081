#pragma once
// "Exactly touching" for the geometry tests of the strip and of the 3D nest.
#include <granstack/model/stack.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace granstack::test {

// Relative tolerance for "exactly touching" in double precision (issue #2): coordinates are
// sums of a few exactly representable multiples of R and one sqrt, so round-off is ~1e-16.
inline constexpr double kTouchTolerance = 1e-12;

// Centre distance less the radii.
inline double gap(const model::Sphere& a, const model::Sphere& b) {
  return (a.centre() - b.centre()).norm() - (a.radius + b.radius);
}

inline bool touching(const model::Sphere& a, const model::Sphere& b) {
  return std::fabs(gap(a, b)) <= kTouchTolerance * (a.radius + b.radius);
}

// The contacts a geometry test designs: each checked to touch exactly, and counted, to be
// compared with touching_pairs (nothing else may touch).
class DesignedContacts {
 public:
  explicit DesignedContacts(const model::Stack& stack) : stack_(stack) {}
  void expect(int a, int b) {
    EXPECT_TRUE(touching(stack_.sphere(a), stack_.sphere(b))) << "ids " << a << " and " << b << " gap "
                                                              << gap(stack_.sphere(a), stack_.sphere(b));
    ++count_;
  }
  long count() const { return count_; }

 private:
  const model::Stack& stack_;
  long count_ = 0;
};

// The pairs of the stack's spheres that touch, every pair tried; a pair that overlaps fails
// the test, naming it.
inline long touching_pairs(const model::Stack& stack) {
  long count = 0;
  const auto& s = stack.spheres();
  for (std::size_t i = 0; i < s.size(); ++i) {
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      if (touching(s[i], s[j])) {
        ++count;
      } else if (!(gap(s[i], s[j]) > 0.0)) {
        ADD_FAILURE() << "ids " << s[i].id << " and " << s[j].id << " overlap by " << -gap(s[i], s[j]);
        return -1;
      }
    }
  }
  return count;
}

}  // namespace granstack::test
