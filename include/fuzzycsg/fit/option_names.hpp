#pragma once
// The names of the fit settings that are chosen from a list, one table per setting, shared by
// the command line (`fuzzycsg fit --ops ...`), report.json and checkpoints (report.hpp), so the
// three cannot drift apart.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg {

template <class E>
struct OptionName {
  std::string_view name;
  E value;
};

template <class E, std::size_t N>
using OptionNames = std::array<OptionName<E>, N>;

inline constexpr OptionNames<OperatorMode, 3> kOperatorModeNames{{
    {"unified", OperatorMode::kUnified},
    {"product", OperatorMode::kProduct},
    {"godel", OperatorMode::kGodel},
}};

inline constexpr OptionNames<OperatorInit, 2> kOperatorInitNames{{
    {"uniform", OperatorInit::kUniform},
    {"balanced", OperatorInit::kBalanced},
}};

inline constexpr OptionNames<OperatorTypes, 2> kOperatorTypesNames{{
    {"all", OperatorTypes::kAll},
    {"union-intersection", OperatorTypes::kUnionIntersection},
}};

inline constexpr OptionNames<InitMode, 3> kInitModeNames{{
    {"random", InitMode::kRandom},
    {"balls", InitMode::kBalls},
    {"surface", InitMode::kSurface},
}};

inline constexpr OptionNames<LrSchedule, 2> kLrScheduleNames{{
    {"constant", LrSchedule::kConstant},
    {"cosine", LrSchedule::kCosine},
}};

inline constexpr OptionNames<SharpnessParam, 2> kSharpnessParamNames{{
    {"linear", SharpnessParam::kLinear},
    {"log", SharpnessParam::kLog},
}};

// Spelled as target.hpp's sampling_scheme_name().
inline const OptionNames<SamplingScheme, 2> kSamplingSchemeNames{{
    {sampling_scheme_name(SamplingScheme::kAppendixA), SamplingScheme::kAppendixA},
    {sampling_scheme_name(SamplingScheme::kRelease), SamplingScheme::kRelease},
}};

// The name of `value` ("?" for a value not in the table).
template <class E, std::size_t N>
constexpr std::string_view option_name(const OptionNames<E, N>& names, E value) {
  for (const OptionName<E>& n : names) {
    if (n.value == value) return n.name;
  }
  return "?";
}

// The value named `name`, if any.
template <class E, std::size_t N>
constexpr std::optional<E> option_value(const OptionNames<E, N>& names, std::string_view name) {
  for (const OptionName<E>& n : names) {
    if (n.name == name) return n.value;
  }
  return std::nullopt;
}

// "a, b or c", for error messages.
template <class E, std::size_t N>
std::string option_list(const OptionNames<E, N>& names) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? " or " : ", ";
    out += names[i].name;
  }
  return out;
}

}  // namespace fuzzycsg
