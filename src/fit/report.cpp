#include "fuzzycsg/fit/report.hpp"

#include <fmt/core.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <type_traits>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/fit/option_names.hpp"

namespace fuzzycsg {

namespace {

using json = nlohmann::json;

json options_to_json(const FitOptions& o) {
  json families = json::array();
  const std::string sharpness(option_name(kSharpnessParamNames, o.sharpness_param));
  for (PrimitiveType f : o.families) families.push_back(std::string(primitive_info(f).name));
  return json{{"prims", o.prims},
              {"families", families},
              {"ops", std::string(option_name(kOperatorModeNames, o.ops))},
              {"op_init", std::string(option_name(kOperatorInitNames, o.op_init))},
              {"op_types", std::string(option_name(kOperatorTypesNames, o.op_types))},
              {"init", std::string(option_name(kInitModeNames, o.init))},
              {"init_range", o.init_range},
              {"init_slope", o.init_slope},
              {"temperature", o.temperature},
              {"temperature_start", o.temperature_start},
              {"temperature_ramp", o.temperature_ramp},
              {"omega", o.omega},
              {"seed", o.seed},
              {"iters", o.iters},
              {"batch", o.batch},
              {"pool", o.pool},
              {"resample_every", o.resample_every},
              {"lr", o.lr},
              {"beta1", o.beta1},
              {"beta2", o.beta2},
              {"adam_eps", o.adam_eps},
              {"lr_schedule", std::string(option_name(kLrScheduleNames, o.lr_schedule))},
              {"lr_end", o.lr_end},
              {"sharpness_param", sharpness},
              {"reseed_every", o.reseed_every},
              {"reseed_until", o.reseed_until},
              {"type_search_every", o.type_search_every},
              {"type_search_from", o.type_search_from},
              {"type_search_until", o.type_search_until},
              {"type_search_points", o.type_search_points},
              {"type_search_switches", o.type_search_switches},
              {"sampling",
               {{"scheme", std::string(sampling_scheme_name(o.sampling.scheme))},
                {"surface", o.sampling.surface},
                {"near", o.sampling.near},
                {"near_distance", o.sampling.near_distance}}},
              {"time_limit", o.time_limit},
              {"prune_threshold", o.prune_threshold},
              {"prune_points", o.prune_points},
              {"prune_max_primitives", o.prune_max_primitives},
              {"metric_points", o.metrics.points},
              {"chamfer", o.metrics.chamfer},
              {"chamfer_resolution", o.metrics.chamfer_resolution},
              {"chamfer_samples", o.metrics.chamfer_samples}};
}

// Reads fields with one-line errors naming the file and the JSON path.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(fmt::format("{}: {}: {}", file_, where, what));
  }

  const json& field(const json& obj, const std::string& where, const char* key) const {
    if (!obj.is_object()) fail(where, "must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) fail(where.empty() ? key : where + "." + key, "missing");
    return *it;
  }

  template <class T>
  T get(const json& obj, const std::string& where, const char* key) const {
    const json& v = field(obj, where, key);
    const std::string path = where.empty() ? key : where + "." + key;
    try {
      if constexpr (std::is_floating_point_v<T>) {
        if (!v.is_number()) fail(path, "must be a number");
      } else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
        if (!v.is_number_integer()) fail(path, "must be an integer");
      }
      return v.get<T>();
    } catch (const json::exception&) {
      fail(path, "has the wrong type");
    }
  }

  // An optional field (absent from files written before it existed).
  template <class T>
  T get_or(const json& obj, const std::string& where, const char* key, T fallback) const {
    if (obj.is_object() && obj.find(key) == obj.end()) return fallback;
    return get<T>(obj, where, key);
  }

  // A setting named from `names` (option_names.hpp); `fallback` when absent, if given.
  template <class E, std::size_t N>
  E choice(const json& obj, const std::string& where, const char* key,
           const OptionNames<E, N>& names,
           std::type_identity_t<std::optional<E>> fallback = std::nullopt) const {
    if (fallback && obj.is_object() && obj.find(key) == obj.end()) return *fallback;
    const std::optional<E> v = option_value(names, get<std::string>(obj, where, key));
    if (!v) fail(where + "." + key, "must be " + option_list(names));
    return *v;
  }

  std::vector<double> numbers(const json& obj, const std::string& where, const char* key) const {
    const json& v = field(obj, where, key);
    const std::string path = where + "." + key;
    if (!v.is_array()) fail(path, "must be an array of numbers");
    std::vector<double> out;
    out.reserve(v.size());
    for (const json& x : v) {
      if (!x.is_number()) fail(path, "must be an array of numbers");
      out.push_back(x.get<double>());
    }
    return out;
  }

 private:
  std::string file_;
};

FitOptions options_from_json(const json& j, const Reader& r, int dim) {
  const std::string w = "settings";
  FitOptions o;
  o.prims = r.get<int>(j, w, "prims");
  for (const json& f : r.field(j, w, "families")) {
    if (!f.is_string()) r.fail(w + ".families", "must be an array of names");
    const std::optional<PrimitiveType> type = primitive_from_name(f.get<std::string>(), dim);
    if (!type) r.fail(w + ".families", "unknown primitive " + f.get<std::string>());
    o.families.push_back(*type);
  }
  o.ops = r.choice(j, w, "ops", kOperatorModeNames);
  // Checkpoints written before there was a choice have none: App. A's uniform logits, all
  // four types, the paper's random start.
  o.op_init = r.choice(j, w, "op_init", kOperatorInitNames, OperatorInit::kUniform);
  o.op_types = r.choice(j, w, "op_types", kOperatorTypesNames, OperatorTypes::kAll);
  o.init = r.choice(j, w, "init", kInitModeNames, InitMode::kRandom);
  o.init_range = r.get<double>(j, w, "init_range");
  o.init_slope = r.get_or<double>(j, w, "init_slope", o.init_slope);
  o.temperature = r.get<double>(j, w, "temperature");
  o.temperature_start = r.get<double>(j, w, "temperature_start");
  o.temperature_ramp = r.get<double>(j, w, "temperature_ramp");
  o.omega = r.get<double>(j, w, "omega");
  o.seed = r.get<std::uint64_t>(j, w, "seed");
  o.iters = r.get<long>(j, w, "iters");
  o.batch = r.get<int>(j, w, "batch");
  o.pool = r.get<std::size_t>(j, w, "pool");
  o.resample_every = r.get<int>(j, w, "resample_every");
  o.lr = r.get<double>(j, w, "lr");
  o.beta1 = r.get<double>(j, w, "beta1");
  o.beta2 = r.get<double>(j, w, "beta2");
  o.adam_eps = r.get<double>(j, w, "adam_eps");
  o.lr_schedule = r.choice(j, w, "lr_schedule", kLrScheduleNames, LrSchedule::kConstant);
  o.lr_end = r.get_or<double>(j, w, "lr_end", o.lr_end);
  // Checkpoints written before there was a choice stepped the sharpness itself.
  o.sharpness_param =
      r.choice(j, w, "sharpness_param", kSharpnessParamNames, SharpnessParam::kLinear);
  o.reseed_every = r.get_or<long>(j, w, "reseed_every", 0L);
  o.reseed_until = r.get_or<double>(j, w, "reseed_until", o.reseed_until);
  o.type_search_every = r.get_or<long>(j, w, "type_search_every", 0L);
  o.type_search_from = r.get_or<double>(j, w, "type_search_from", o.type_search_from);
  o.type_search_until = r.get_or<double>(j, w, "type_search_until", o.type_search_until);
  o.type_search_points = r.get_or<std::size_t>(j, w, "type_search_points", o.type_search_points);
  o.type_search_switches = r.get_or<int>(j, w, "type_search_switches", o.type_search_switches);
  const json& s = r.field(j, w, "sampling");
  o.sampling.surface = r.get<double>(s, w + ".sampling", "surface");
  o.sampling.near = r.get<double>(s, w + ".sampling", "near");
  o.sampling.near_distance = r.get<double>(s, w + ".sampling", "near_distance");
  // Checkpoints written before there was a choice of scheme have none: App. A's.
  o.sampling.scheme =
      r.choice(s, w + ".sampling", "scheme", kSamplingSchemeNames, SamplingScheme::kAppendixA);
  o.time_limit = r.get<double>(j, w, "time_limit");
  o.prune_threshold = r.get<double>(j, w, "prune_threshold");
  o.prune_points = r.get<std::size_t>(j, w, "prune_points");
  // Checkpoints written before there was a limit have none.
  o.prune_max_primitives = r.get_or<int>(j, w, "prune_max_primitives", 0);
  o.metrics.points = r.get<std::size_t>(j, w, "metric_points");
  o.metrics.chamfer = r.get<bool>(j, w, "chamfer");
  o.metrics.chamfer_resolution = r.get<int>(j, w, "chamfer_resolution");
  o.metrics.chamfer_samples = r.get<std::size_t>(j, w, "chamfer_samples");
  return o;
}

json curve_json(const std::vector<LossPoint>& curve) {
  json out = json::array();
  for (const LossPoint& p : curve) out.push_back(json::array({p.step, p.loss, p.seconds}));
  return out;
}

json metrics_json(const std::optional<Metrics>& m) {
  if (!m) return nullptr;
  json out{{"mse", m->mse}, {"iou", m->iou}, {"points", m->points}};
  out["chamfer"] = m->chamfer ? json(*m->chamfer) : json(nullptr);
  out["hausdorff"] = m->hausdorff ? json(*m->hausdorff) : json(nullptr);
  return out;
}

json counts_json(const Tree& tree) {
  const TreeCounts c = count(tree);
  return json{{"primitives", c.primitives},
              {"operators", c.operators},
              {"nodes", c.primitives + c.operators},
              {"parameters", c.parameters},
              {"depth", c.depth}};
}

}  // namespace

std::string_view operator_mode_name(OperatorMode m) { return option_name(kOperatorModeNames, m); }

std::string fit_options_json(const FitOptions& options) { return options_to_json(options).dump(2); }

std::string checkpoint_to_string(const Checkpoint& c) {
  const TrainState& s = c.state;
  json j{{"format", "fuzzycsg-checkpoint"},
         {"version", 1},
         {"target", c.target},
         {"dim", c.dim},
         {"settings", options_to_json(c.options)},
         {"state",
          {{"step", s.step},
           {"params", s.params},
           {"adam_m", s.m},
           {"adam_v", s.v},
           {"rng", s.rng_at_resample},
           {"pool_step", s.pool_step},
           {"curve", curve_json(s.curve)},
           {"loss_sum", s.loss_sum},
           {"loss_count", s.loss_count},
           {"seconds", s.seconds},
           {"reseeded", s.reseeded},
           {"switched", s.switched}}}};
  return j.dump(1) + "\n";
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open checkpoint", file));
  std::stringstream buffer;
  buffer << in.rdbuf();
  json j;
  try {
    j = json::parse(buffer.str());
  } catch (const json::parse_error& e) {
    throw InputError(fmt::format("{}: not a checkpoint (JSON error at byte {})", file, e.byte));
  }
  const Reader r(file);
  if (!j.is_object() || j.value("format", "") != "fuzzycsg-checkpoint") {
    r.fail("format", "must be \"fuzzycsg-checkpoint\"");
  }
  if (r.get<int>(j, "", "version") != 1) r.fail("version", "must be 1");
  Checkpoint c;
  c.target = r.get<std::string>(j, "", "target");
  c.dim = r.get<int>(j, "", "dim");
  if (c.dim != 2 && c.dim != 3) r.fail("dim", "must be 2 or 3");
  c.options = options_from_json(r.field(j, "", "settings"), r, c.dim);
  const json& s = r.field(j, "", "state");
  const std::string w = "state";
  c.state.step = r.get<long>(s, w, "step");
  c.state.params = r.numbers(s, w, "params");
  c.state.m = r.numbers(s, w, "adam_m");
  c.state.v = r.numbers(s, w, "adam_v");
  c.state.rng_at_resample = r.get<std::string>(s, w, "rng");
  c.state.pool_step = r.get<long>(s, w, "pool_step");
  c.state.loss_sum = r.get<double>(s, w, "loss_sum");
  c.state.loss_count = r.get<long>(s, w, "loss_count");
  c.state.seconds = r.get<double>(s, w, "seconds");
  c.state.reseeded = r.get_or<long>(s, w, "reseeded", 0L);
  c.state.switched = r.get_or<long>(s, w, "switched", 0L);
  const json& curve = r.field(s, w, "curve");
  if (!curve.is_array()) r.fail("state.curve", "must be an array");
  for (const json& p : curve) {
    if (!p.is_array() || p.size() != 3 || !p[0].is_number_integer() || !p[1].is_number() ||
        !p[2].is_number()) {
      r.fail("state.curve", "entries must be [step, loss, seconds]");
    }
    c.state.curve.push_back({p[0].get<long>(), p[1].get<double>(), p[2].get<double>()});
  }
  if (c.state.step < 0 || c.state.pool_step > c.state.step) r.fail("state.step", "out of range");
  if (c.state.m.size() != c.state.params.size() || c.state.v.size() != c.state.params.size()) {
    r.fail("state.adam_m", "must have as many values as state.params");
  }
  return c;
}

std::string fit_report_json(const FitResult& r, const FitOptions& o, const ReportContext& ctx) {
  json j;
  j["fuzzycsg"] = "0.1.0";
  if (!ctx.command_line.empty()) j["command"] = ctx.command_line;
  j["target"] = {{"path", ctx.target_path}};
  if (ctx.target) {
    j["target"]["kind"] = ctx.target->kind();
    j["target"]["dim"] = ctx.target->dim();
    j["target"]["description"] = ctx.target->describe();
    // Training ran in the normalised box x_norm = scale * x + translate (x in the target's own
    // coordinates); the trees written are mapped back to the target's coordinates.
    const Similarity n = ctx.target->normalisation();
    j["target"]["normalisation"] = {
        {"scale", n.scale},
        {"translate",
         std::vector<double>(n.translate.begin(), n.translate.begin() + ctx.target->dim())},
        {"trees", "target coordinates"}};
  }
  j["settings"] = options_to_json(o);
  j["seed"] = o.seed;
  j["threads"] = ctx.threads;
  j["stop"] = std::string(stop_reason_name(r.stop));
  j["steps"] = r.state.step;
  j["final_loss"] = r.state.curve.empty() ? json(nullptr) : json(r.state.curve.back().loss);
  j["operators"] = {{"unified", r.operators_total},
                    {"changed_type", r.operators_changed},
                    {"changed_structure", r.operators_restructured},
                    {"type_searches", r.type_searches},
                    {"type_switches", r.type_switches}};
  j["init"] = {{"leaves_from_target", r.initialised_leaves}, {"reseeded_leaves", r.reseeded}};
  j["counts"] = {{"trained", counts_json(r.trained)}};
  if (r.stop != StopReason::kNonFinite) {
    j["counts"]["pruned"] = counts_json(r.pruned);
  }
  j["metrics"] = {{"trained", metrics_json(r.metrics_trained)},
                  {"pruned", metrics_json(r.metrics_pruned)}};
  const double sps =
      r.train_seconds > 0 ? static_cast<double>(r.state.step) / r.train_seconds : 0.0;
  j["timings"] = {{"train_seconds", r.train_seconds},
                  {"steps_per_second", sps},
                  {"prune_seconds", r.prune_seconds},
                  {"metrics_seconds", r.metrics_seconds}};
  j["loss_curve"] = curve_json(r.state.curve);
  return j.dump(2) + "\n";
}

}  // namespace fuzzycsg
