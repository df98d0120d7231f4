// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/analysis/convergence.hpp>
#include "test_util.hpp"

using namespace vrsph;

TEST(Convergence, PairwiseAndLeastSquaresOrders) {
  const std::vector<double> h{0.1, 0.05, 0.025, 0.0125};
  std::vector<double> e;
  for (double x : h) e.push_back(3 * x * x * (1 + 0.01 * x));
  const auto o = pairwise_orders(h, e);
  EXPECT_TRUE(std::isnan(o[0]));
  for (std::size_t k = 1; k < o.size(); ++k) EXPECT_NEAR(o[k], 2.0, 0.01);
  EXPECT_NEAR(least_squares_order(h, e), 2.0, 0.01);
  const std::vector<double> z{1, 0, 1, 1};
  EXPECT_TRUE(std::isnan(pairwise_orders(h, z)[1]));
  EXPECT_TRUE(std::isnan(least_squares_order(std::vector<double>{1}, std::vector<double>{1})));
}
