// The settings chosen by name (fuzzycsg/fit/option_names.hpp) in checkpoints and reports: every
// name round-trips, a wrong one is an error naming the field and the choices, and a field that
// older checkpoints lack takes its documented default.

#include <gtest/gtest.h>

#include <string>

#include "fit/checkpoint_support.hpp"
#include "fit/fit_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/fit/option_names.hpp"
#include "fuzzycsg/fit/report.hpp"

namespace fuzzycsg {
namespace {

using testing::write_temp;

Checkpoint small_checkpoint(const FitOptions& options) {
  return testing::small_checkpoint(options, 3, "part.obj");
}

// The checkpoint's text with `"key": "value"` replaced by `replacement` (empty: removed).
std::string edited(const std::string& text, const std::string& key, const std::string& value,
                   const std::string& replacement) {
  const std::string field = "\"" + key + "\": \"" + value + "\",";
  const std::size_t at = text.find(field);
  EXPECT_NE(at, std::string::npos) << field;
  if (at == std::string::npos) return text;
  std::string out = text;
  out.replace(at, field.size(), replacement);
  return out;
}

TEST(OptionNames, ListsAndLookups) {
  EXPECT_EQ(option_list(kOperatorModeNames), "unified, product or godel");
  EXPECT_EQ(option_list(kOperatorTypesNames), "all or union-intersection");
  EXPECT_EQ(option_value(kInitModeNames, "surface"), InitMode::kSurface);
  EXPECT_EQ(option_value(kInitModeNames, "Surface"), std::nullopt);
  EXPECT_EQ(option_name(kLrScheduleNames, LrSchedule::kCosine), "cosine");
  EXPECT_EQ(option_name(kSamplingSchemeNames, SamplingScheme::kRelease), "release");
}

TEST(OptionNames, EveryNameRoundTripsThroughACheckpoint) {
  int checked = 0;
  auto round_trip = [&](const FitOptions& o) {
    const std::string path =
        write_temp("fuzzycsg_option_names.json", checkpoint_to_string(small_checkpoint(o)));
    const Checkpoint back = read_checkpoint(path);
    EXPECT_EQ(back.options.ops, o.ops);
    EXPECT_EQ(back.options.op_init, o.op_init);
    EXPECT_EQ(back.options.op_types, o.op_types);
    EXPECT_EQ(back.options.init, o.init);
    EXPECT_EQ(back.options.lr_schedule, o.lr_schedule);
    EXPECT_EQ(back.options.sharpness_param, o.sharpness_param);
    ++checked;
  };
  // Every value of one table, set in otherwise default options.
  auto each = [&](const auto& names, auto FitOptions::*field) {
    for (const auto& n : names) {
      FitOptions o;
      o.*field = n.value;
      round_trip(o);
    }
  };
  each(kOperatorModeNames, &FitOptions::ops);
  each(kOperatorInitNames, &FitOptions::op_init);
  each(kOperatorTypesNames, &FitOptions::op_types);
  each(kInitModeNames, &FitOptions::init);
  each(kLrScheduleNames, &FitOptions::lr_schedule);
  each(kSharpnessParamNames, &FitOptions::sharpness_param);
  EXPECT_EQ(checked, 14);
}

TEST(OptionNames, BadNamesAndOlderCheckpoints) {
  FitOptions o;
  o.ops = OperatorMode::kProduct;
  o.op_init = OperatorInit::kBalanced;
  o.op_types = OperatorTypes::kUnionIntersection;
  o.init = InitMode::kBalls;
  o.lr_schedule = LrSchedule::kCosine;
  o.sharpness_param = SharpnessParam::kLog;
  o.prune_max_primitives = 7;
  const std::string good = checkpoint_to_string(small_checkpoint(o));
  EXPECT_EQ(read_checkpoint(write_temp("fuzzycsg_good.json", good)).options.prune_max_primitives,
            7);

  const std::string bad_ops =
      write_temp("fuzzycsg_bad_ops.json", edited(good, "ops", "product", "\"ops\": \"fuzzy\","));
  EXPECT_EQ(testing::checkpoint_read_error(bad_ops),
            bad_ops + ": settings.ops: must be unified, product or godel");
  const std::string bad_types =
      write_temp("fuzzycsg_bad_types.json",
                 edited(good, "op_types", "union-intersection", "\"op_types\": \"union\","));
  EXPECT_EQ(testing::checkpoint_read_error(bad_types),
            bad_types + ": settings.op_types: must be all or union-intersection");
  const std::string number =
      write_temp("fuzzycsg_bad_init.json", edited(good, "init", "balls", "\"init\": 2,"));
  EXPECT_NE(testing::checkpoint_read_error(number).find("settings.init"), std::string::npos);

  // "ops" has always been written: a checkpoint without it is broken.
  const std::string no_ops = write_temp("fuzzycsg_no_ops.json", edited(good, "ops", "product", ""));
  EXPECT_EQ(testing::checkpoint_read_error(no_ops), no_ops + ": settings.ops: missing");
  // The others came later; without them a checkpoint means App. A's choices.
  std::string older = edited(good, "op_init", "balanced", "");
  older = edited(older, "op_types", "union-intersection", "");
  older = edited(older, "init", "balls", "");
  older = edited(older, "lr_schedule", "cosine", "");
  older = edited(older, "sharpness_param", "log", "");
  const std::string limit = "\"prune_max_primitives\": 7,";
  ASSERT_NE(older.find(limit), std::string::npos);
  older.replace(older.find(limit), limit.size(), "");
  const Checkpoint back = read_checkpoint(write_temp("fuzzycsg_older.json", older));
  EXPECT_EQ(back.options.ops, OperatorMode::kProduct);
  EXPECT_EQ(back.options.op_init, OperatorInit::kUniform);
  EXPECT_EQ(back.options.op_types, OperatorTypes::kAll);
  EXPECT_EQ(back.options.init, InitMode::kRandom);
  EXPECT_EQ(back.options.lr_schedule, LrSchedule::kConstant);
  EXPECT_EQ(back.options.sharpness_param, SharpnessParam::kLinear);
  EXPECT_EQ(back.options.prune_max_primitives, 0);
}

}  // namespace
}  // namespace fuzzycsg
