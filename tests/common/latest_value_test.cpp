#include "hapsim/common/latest_value.h"

#include <thread>

#include <gtest/gtest.h>

namespace hapsim::common {
namespace {

struct Pair {
  long a = 0, b = 0;  // always written equal: a torn read would show a != b
};

TEST(LatestValue, ConsumerSeesNewestValuesInOrderAndNeverTorn) {
  LatestValue<Pair> box;
  constexpr long kCount = 200000;
  std::thread producer([&] {
    for (long i = 1; i <= kCount; ++i) box.Publish({i, i});
  });
  long last = 0, takes = 0;
  Pair p;
  while (last < kCount) {
    if (box.TakeIfNew(&p)) {
      ASSERT_EQ(p.a, p.b);
      ASSERT_GT(p.a, last);  // strictly newer each time
      last = p.a;
      ++takes;
    }
  }
  producer.join();
  EXPECT_EQ(last, kCount);  // the final value always arrives
  EXPECT_GT(takes, 0);
  EXPECT_FALSE(box.TakeIfNew(&p));  // nothing new after the last take
}

}  // namespace
}  // namespace hapsim::common
