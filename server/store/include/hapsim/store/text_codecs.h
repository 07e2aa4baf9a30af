// The text forms of the results database's list columns (docs/recording.md, "The results database").
// Doubles are written as %.17g (locale-free), so they read back bit-exact
// (NaN reads back as a quiet NaN). Names are escaped so that any name
// survives: '%' and the separators become %XX.
#pragma once
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hapsim::service::store_codec {

// "name=value;name=value" (sessions.params). Decode throws
// std::invalid_argument on malformed text.
std::string EncodeParams(const std::map<std::string, double>& params);
std::map<std::string, double> DecodeParams(std::string_view text);

// "v,v,v" (score_sheets.indicators, trials.peak_force_in_layer_N).
std::string EncodeDoubles(std::span<const double> values);
std::vector<double> DecodeDoubles(std::string_view text);  // "" -> {}; throws std::invalid_argument

// "a|b|c" (trials.layer_names). "" is the empty list.
std::string JoinNames(const std::vector<std::string>& names);
std::vector<std::string> SplitNames(std::string_view text);

}  // namespace hapsim::service::store_codec
