// report.json of a refinement built from a small result made by hand: the header, the settings
// echoed, the loss and check curves, the time per step and every parameter before and after.
#include "fuzzycsg/diffcsg/report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

using json = nlohmann::json;

Tree one_box() {
  return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"op": "union", "children": [{"type": "box", "size": [1, 0.8, 0.6]},
        {"type": "sphere", "radius": 0.5, "translate": [0.6, 0, 0]}]}})");
}

struct Fixture {
  Tree model = one_box();
  Scene scene = scene_from_tree(model, "model");
  RefineTarget target;
  RefineOptions options;
  RefineResult result;
  RefineReportContext context{"fuzzycsg refine m.json", "m.json", "t.off", "mesh", true};

  Fixture() {
    target.cameras.push_back(Camera::orbit({0, 0, 0}, 30, 25, 4, 16, 12, 40));
    target.cameras.push_back(Camera::orbit({0, 0, 0}, 150, 25, 4, 16, 12, 40));
    target.shading = Shading::kColours;
    options.method = Method::kCmaes;
    options.loss = Loss::kTanh;
    options.iterations = 9;
    options.lr = 0.03;
    options.stop_mse = 1e-3;
    options.seed = 11;
    options.intersection_aa = false;
    result.tree = model;
    result.tree.params.at(0).value += 0.25;
    result.loss = {0.5, 0.25};
    result.check_mse = {{0, 0.4}, {1, 0.2}};
    result.steps = 2;
    result.converged = true;
    const std::vector<std::string> paths = node_paths(model);
    const auto sphere = std::find(paths.begin(), paths.end(), "root.children[1]");
    result.unseen_primitives = {static_cast<int>(sphere - paths.begin())};
    result.seconds_visibility = 1.0;
    result.seconds_backward = 0.5;
    result.seconds = 3.0;
  }
};

TEST(DiffcsgReport, EchoesTheSettingsAndTheResult) {
  const Fixture f;
  const json j =
      json::parse(refine_report_json(f.model, f.scene, f.target, f.options, f.result, f.context));
  EXPECT_EQ(j["format"], "fuzzycsg-refine-report");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["command_line"], "fuzzycsg refine m.json");
  EXPECT_EQ(j["model"], "m.json");
  EXPECT_EQ(j["target"], "t.off");
  EXPECT_EQ(j["target_kind"], "mesh");

  const json& s = j["settings"];
  EXPECT_EQ(s["method"], "cmaes");
  EXPECT_EQ(s["shading"], "colours");
  EXPECT_EQ(s["loss"], "tanh");
  EXPECT_EQ(s["views"], 2);
  EXPECT_EQ(s["size"], json::parse("[16, 12]"));
  EXPECT_EQ(s["iters"], 9);
  EXPECT_DOUBLE_EQ(s["lr"].get<double>(), 0.03);
  EXPECT_DOUBLE_EQ(s["stop"].get<double>(), 1e-3);
  EXPECT_EQ(s["shared_only"], true);
  EXPECT_EQ(s["seed"], 11);
  EXPECT_EQ(s["intersection_aa"], false);
  EXPECT_DOUBLE_EQ(s["fov"].get<double>(), 40.0);
  EXPECT_EQ(s["triangles"], f.scene.triangle_count());
  EXPECT_GT(s["triangles"].get<int>(), 12);  // a box and a sphere

  EXPECT_EQ(j["steps"], 2);
  EXPECT_EQ(j["converged"], true);
  EXPECT_EQ(j["vanished"], false);
  EXPECT_EQ(j["unseen_primitives"], json::parse(R"(["root.children[1]"])"));
  EXPECT_EQ(j["loss"], json::parse("[0.5, 0.25]"));
  EXPECT_EQ(j["check_mse"], json::parse("[[0, 0.4], [1, 0.2]]"));
  EXPECT_DOUBLE_EQ(j["seconds_per_step"]["visibility"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["seconds_per_step"]["backward"].get<double>(), 0.25);

  ASSERT_EQ(j["parameters"].size(), f.model.params.size());
  const json& p = j["parameters"][0];
  EXPECT_EQ(p["name"], f.model.params.at(0).name);
  EXPECT_DOUBLE_EQ(p["before"].get<double>(), f.model.params.at(0).value);
  EXPECT_DOUBLE_EQ(p["after"].get<double>(), f.model.params.at(0).value + 0.25);
}

TEST(DiffcsgReport, KeysAreSorted) {
  const Fixture f;
  const std::string text =
      refine_report_json(f.model, f.scene, f.target, f.options, f.result, f.context);
  EXPECT_TRUE(text.starts_with("{\n  \"check_mse\": ["));
  EXPECT_EQ(text.back(), '\n');
  const nlohmann::ordered_json in_order = nlohmann::ordered_json::parse(text);
  std::vector<std::string> keys;
  for (const auto& [key, value] : in_order.items()) keys.push_back(key);
  EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
  EXPECT_EQ(keys.size(), 16u);
}

TEST(DiffcsgReport, RefusesATargetWithoutCameras) {
  Fixture f;
  f.target.cameras.clear();
  EXPECT_THROW(refine_report_json(f.model, f.scene, f.target, f.options, f.result, f.context),
               std::invalid_argument);
}

TEST(DiffcsgReport, MethodNamesRoundTrip) {
  for (const Method m : {Method::kAdam, Method::kCmaes}) {
    EXPECT_EQ(method_from_name(method_name(m)), m);
  }
  EXPECT_FALSE(method_from_name("sgd").has_value());
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
