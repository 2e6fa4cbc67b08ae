// The sampling scheme in the settings of checkpoints and reports.

#include <gtest/gtest.h>

#include <string>

#include "fit/checkpoint_support.hpp"
#include "fit/fit_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/fit/report.hpp"

namespace fuzzycsg {
namespace {

using testing::write_temp;

Checkpoint small_checkpoint(SamplingScheme scheme) {
  FitOptions options;
  options.sampling.scheme = scheme;
  return testing::small_checkpoint(options, 2, "logo.png");
}

TEST(SamplerSettings, RoundTripThroughACheckpoint) {
  for (SamplingScheme scheme : {SamplingScheme::kAppendixA, SamplingScheme::kRelease}) {
    const std::string text = checkpoint_to_string(small_checkpoint(scheme));
    EXPECT_NE(
        text.find(std::string("\"scheme\": \"") + std::string(sampling_scheme_name(scheme)) + "\""),
        std::string::npos);
    const Checkpoint back = read_checkpoint(write_temp("fuzzycsg_scheme.json", text));
    EXPECT_EQ(back.options.sampling.scheme, scheme);
  }
  EXPECT_NE(fit_options_json(small_checkpoint(SamplingScheme::kRelease).options)
                .find("\"scheme\": \"release\""),
            std::string::npos);
}

TEST(SamplerSettings, OlderCheckpointsAndBadNames) {
  const std::string good = checkpoint_to_string(small_checkpoint(SamplingScheme::kRelease));
  const std::string field = "\"scheme\": \"release\",";
  const std::size_t at = good.find(field);
  ASSERT_NE(at, std::string::npos);

  // Written before there was a choice: App. A's sampler.
  std::string older = good;
  older.erase(at, field.size());
  const std::string older_path = write_temp("fuzzycsg_scheme_older.json", older);
  EXPECT_EQ(testing::checkpoint_read_error(older_path), "no error");
  EXPECT_EQ(read_checkpoint(older_path).options.sampling.scheme, SamplingScheme::kAppendixA);

  std::string bad = good;
  bad.replace(at, field.size(), "\"scheme\": \"uniform\",");
  const std::string bad_path = write_temp("fuzzycsg_scheme_bad.json", bad);
  EXPECT_EQ(testing::checkpoint_read_error(bad_path),
            bad_path + ": settings.sampling.scheme: must be appendix-a or release");
  bad.replace(bad.find("\"uniform\"", at), 9, "4");
  const std::string number_path = write_temp("fuzzycsg_scheme_number.json", bad);
  EXPECT_NE(testing::checkpoint_read_error(number_path).find("settings.sampling.scheme"),
            std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg
