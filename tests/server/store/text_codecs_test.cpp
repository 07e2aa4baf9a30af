// The list columns' text forms read back exactly what was written.
#include "hapsim/store/text_codecs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hapsim::service::store_codec {
namespace {

TEST(StoreTextCodecs, DoublesRoundTripBitForBit) {
  const std::vector<double> values = {0.1,
                                      1.0 / 3.0,
                                      -2.5e-310,
                                      1e308,
                                      0.0,
                                      12345678901234567.0,
                                      std::numeric_limits<double>::infinity(),
                                      std::nextafter(1.0, 2.0)};
  const std::string text = EncodeDoubles(values);
  EXPECT_EQ(text.find(' '), std::string::npos);
  EXPECT_EQ(DecodeDoubles(text), values);
  EXPECT_TRUE(DecodeDoubles("").empty());
  const auto nan = DecodeDoubles(EncodeDoubles(std::vector<double>{std::nan("")}));
  ASSERT_EQ(nan.size(), 1u);
  EXPECT_TRUE(std::isnan(nan[0]));
  EXPECT_THROW(DecodeDoubles("1,x"), std::invalid_argument);
  EXPECT_THROW(DecodeDoubles("1,"), std::invalid_argument);
}

TEST(StoreTextCodecs, ParamsRoundTripWhateverTheirNames) {
  const std::map<std::string, double> params = {
      {"stiffness_N_per_m", 0.1}, {"a=b;c", 1.0 / 3.0}, {"100%", -1}, {"", 2}, {"%3B", 3}};
  const std::string text = EncodeParams(params);
  EXPECT_EQ(DecodeParams(text), params);
  EXPECT_EQ(EncodeParams({{"k", 0.1}}), "k=0.10000000000000001");  // %.17g
  EXPECT_TRUE(DecodeParams("").empty());
  EXPECT_THROW(DecodeParams("novalue"), std::invalid_argument);
  EXPECT_THROW(DecodeParams("bad%zz=1"), std::invalid_argument);
}

TEST(StoreTextCodecs, NamesRoundTripWithTheSeparatorInside) {
  const std::vector<std::string> names = {"skin", "fat|subcutis", "50%", "", "muscle"};
  EXPECT_EQ(SplitNames(JoinNames(names)), names);
  EXPECT_EQ(JoinNames({"skin", "fat"}), "skin|fat");
  EXPECT_TRUE(SplitNames("").empty());
}

}  // namespace
}  // namespace hapsim::service::store_codec
