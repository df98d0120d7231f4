// SPDX-License-Identifier: BSD-3-Clause
// Buffers re-sized for overwriting (core/uninitialized.hpp): a size that changes by a few
// entries from step to step, as a moving cloud's pair count does, re-allocates at most once.
#include <vrsph/core/uninitialized.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(ResizeForOverwrite, GrowsOnceWithHeadroomAndKeepsTheBufferAfterwards) {
  UninitVector<double> v;
  resize_for_overwrite(v, 1600);
  EXPECT_EQ(v.size(), 1600u);
  EXPECT_GE(v.capacity(), 1700u);  // 1/16 of headroom
  const double* first = v.data();
  for (const std::size_t n : {1500u, 1650u, 1700u, 1200u}) {  // as a pair count fluctuates
    resize_for_overwrite(v, n);
    EXPECT_EQ(v.size(), n);
    EXPECT_EQ(v.data(), first) << n;
  }
  resize_for_overwrite(v, 3200);  // beyond the headroom: one new buffer, not twice the size
  EXPECT_EQ(v.size(), 3200u);
  EXPECT_GE(v.capacity(), 3400u);
  EXPECT_LT(v.capacity(), 3600u);
}

TEST(ReserveForOverwrite, GrowsWithHeadroomAndKeepsABufferWithRoom) {
  std::vector<double> v(100, 1.0);
  reserve_for_overwrite(v, 80);  // room enough: nothing changes
  EXPECT_EQ(v.size(), 100u);
  EXPECT_EQ(v[99], 1.0);
  reserve_for_overwrite(v, 160);  // grown: the old contents are not kept
  EXPECT_GE(v.capacity(), 170u);
  v.assign(160, 2.0);
  const double* first = v.data();
  reserve_for_overwrite(v, 168);
  v.assign(168, 3.0);
  EXPECT_EQ(v.data(), first);
}
