// Search over the types of unified operators (see fuzzycsg/fit/types.hpp).
#include "fuzzycsg/fit/types.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <utility>

#include "fuzzycsg/core/logic.hpp"

namespace fuzzycsg {

namespace {

double value_or(std::span<const double> params, const std::optional<ParamRef>& r, double v) {
  return r ? params[r->index] : v;
}

double mse(const Evaluator& ev, std::span<const double> params, const SampleSet& s,
           std::vector<float>& occ) {
  occ.resize(s.size());
  ev.forward(params, s.points, occ);
  double sum = 0.0;
  for (std::size_t i = 0; i < occ.size(); ++i) {
    const double r = static_cast<double>(occ[i]) - static_cast<double>(s.occupancy[i]);
    sum += r * r;
  }
  return occ.empty() ? 0.0 : sum / static_cast<double>(occ.size());
}

struct Switch {
  int node = -1;
  int from = 0, to = 0;
  double change = 0.0;  // of the choosing sample's MSE
};

}  // namespace

std::array<double, 4> unified_weights_at(const Node& node, std::span<const double> params) {
  std::array<double, 4> w{};
  for (int i = 0; i < 4; ++i) w[static_cast<std::size_t>(i)] = params[node.unified[i].index];
  if (node.unified_logits) {
    w = logic::unified_weights(w, value_or(params, node.temperature, 1000.0),
                               value_or(params, node.omega, 10.0));
  }
  return w;
}

int unified_type(const Node& node, std::span<const double> params) {
  const auto w = unified_weights_at(node, params);
  return static_cast<int>(std::max_element(w.begin(), w.end()) - w.begin());
}

std::array<double, 3> swap_delta(const std::array<double, 4>& c, int i, int j) {
  std::array<double, 4> s = c;
  std::swap(s[static_cast<std::size_t>(i)], s[static_cast<std::size_t>(j)]);
  // (a, b, d) = (c1 + c2, c1 + c3, c0 - c1 - c2 - c3), core/logic.hpp
  auto abd = [](const std::array<double, 4>& w) {
    return std::array<double, 3>{w[1] + w[2], w[1] + w[3], w[0] - w[1] - w[2] - w[3]};
  };
  const auto a = abd(c), b = abd(s);
  return {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
}

void swap_unified_entries(const Node& node, int i, int j, std::span<double> params,
                          std::span<double> adam_m, std::span<double> adam_v) {
  const std::size_t pi = node.unified[static_cast<std::size_t>(i)].index;
  const std::size_t pj = node.unified[static_cast<std::size_t>(j)].index;
  std::swap(params[pi], params[pj]);
  if (!adam_m.empty()) std::swap(adam_m[pi], adam_m[pj]);
  if (!adam_v.empty()) std::swap(adam_v[pi], adam_v[pj]);
}

TypeSearchReport search_operator_types(const Tree& model, const Evaluator& evaluator,
                                       const Target& target, std::span<double> params,
                                       std::span<double> adam_m, std::span<double> adam_v,
                                       const TypeSearchOptions& o, Rng& rng) {
  TypeSearchReport rep;
  const std::size_t nodes = model.nodes.size();
  // Operators whose four weights are their own and of which at least two are free (a weight
  // shared with another operator cannot be swapped for this operator alone); switches are made
  // between free weights only (a fixed one, as the differences of OperatorTypes::
  // kUnionIntersection, keeps its place).
  std::vector<int> uses(model.params.size(), 0);
  for (const Node& n : model.nodes) {
    if (n.kind != NodeKind::kOperator || n.op != OpKind::kUnified) continue;
    for (const ParamRef& r : n.unified) ++uses[r.index];
  }
  std::vector<int> unified;
  for (std::size_t k = 0; k < nodes; ++k) {
    const Node& n = model.nodes[k];
    if (n.kind != NodeKind::kOperator || n.op != OpKind::kUnified || n.children.size() != 2 ||
        n.unified.size() != 4) {
      continue;
    }
    bool own = true;
    int free = 0;
    for (const ParamRef& r : n.unified) {
      own = own && uses[r.index] == 1;
      free += model.params.at(r.index).fixed ? 0 : 1;
    }
    if (own && free >= 2) unified.push_back(static_cast<int>(k));
  }
  rep.operators = static_cast<int>(unified.size());
  if (unified.empty()) return rep;
  std::vector<int> parent(nodes, -1);
  for (std::size_t k = 0; k < nodes; ++k) {
    for (int c : model.nodes[k].children) parent[static_cast<std::size_t>(c)] = static_cast<int>(k);
  }

  const SampleSet choose = draw_samples(target, o.points, o.sampling, rng);
  const SampleSet judge = draw_samples(target, o.points, o.sampling, rng);
  std::vector<float> occ;
  double judged = mse(evaluator, params, judge, occ);
  rep.loss_before = judged;

  std::vector<BilinearEdit> edits;
  std::vector<Switch> switches;
  std::vector<double> changes;
  std::vector<char> chosen(nodes), below(nodes);  // chosen; has a chosen node below it
  for (int round = 0; round < o.rounds; ++round) {
    ++rep.rounds;
    edits.clear();
    switches.clear();
    for (int k : unified) {
      const Node& n = model.nodes[static_cast<std::size_t>(k)];
      const auto c = unified_weights_at(n, params);
      const int from = static_cast<int>(std::max_element(c.begin(), c.end()) - c.begin());
      if (model.params.at(n.unified[static_cast<std::size_t>(from)].index).fixed) continue;
      for (int to = 0; to < 4; ++to) {
        if (to == from || model.params.at(n.unified[static_cast<std::size_t>(to)].index).fixed) {
          continue;
        }
        edits.push_back({k, swap_delta(c, from, to)});
        switches.push_back({k, from, to, 0.0});
      }
    }
    changes.resize(edits.size());
    Loss loss;
    loss.kind = Loss::Kind::kMse;
    loss.targets = choose.occupancy;
    evaluator.edit_loss_changes(params, choose.points, loss, edits, changes);
    std::vector<std::size_t> better;
    for (std::size_t e = 0; e < switches.size(); ++e) {
      switches[e].change = changes[e];
      if (changes[e] < -o.min_gain) better.push_back(e);
    }
    if (round == 0) rep.proposed = static_cast<int>(better.size());
    if (better.empty()) break;
    std::stable_sort(better.begin(), better.end(), [&](std::size_t x, std::size_t y) {
      return switches[x].change < switches[y].change;
    });
    // Best first, at most one per node and none on the path of another.
    std::fill(chosen.begin(), chosen.end(), 0);
    std::fill(below.begin(), below.end(), 0);
    std::vector<const Switch*> take;
    for (std::size_t e : better) {
      if (static_cast<int>(take.size()) >= o.max_switches) break;
      const int k = switches[e].node;
      if (chosen[static_cast<std::size_t>(k)] || below[static_cast<std::size_t>(k)]) continue;
      bool free = true;
      for (int p = parent[static_cast<std::size_t>(k)]; p >= 0 && free;
           p = parent[static_cast<std::size_t>(p)]) {
        free = !chosen[static_cast<std::size_t>(p)];
      }
      if (!free) continue;
      chosen[static_cast<std::size_t>(k)] = 1;
      for (int p = parent[static_cast<std::size_t>(k)]; p >= 0;
           p = parent[static_cast<std::size_t>(p)]) {
        below[static_cast<std::size_t>(p)] = 1;
      }
      take.push_back(&switches[e]);
    }
    auto apply = [&](const Switch& s) {
      swap_unified_entries(model.nodes[static_cast<std::size_t>(s.node)], s.from, s.to, params,
                           adam_m, adam_v);
    };
    for (const Switch* s : take) apply(*s);
    double after = mse(evaluator, params, judge, occ);
    if (after < judged - o.min_gain) {
      judged = after;
      rep.switched += static_cast<int>(take.size());
      continue;
    }
    for (auto it = take.rbegin(); it != take.rend(); ++it) apply(**it);  // a swap undoes itself
    if (take.size() == 1) break;
    apply(*take.front());
    after = mse(evaluator, params, judge, occ);
    if (after < judged - o.min_gain) {
      judged = after;
      rep.switched += 1;
      continue;
    }
    apply(*take.front());
    break;
  }
  rep.loss_after = judged;
  return rep;
}

std::vector<int> structure_bits(const Tree& tree, std::span<const int> types) {
  constexpr std::array<std::array<bool, 3>, 4> kNeg{
      {{false, false, false}, {true, true, true}, {false, false, true}, {false, true, false}}};
  std::vector<bool> negated(tree.nodes.size(), false);  // by the parent
  for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
    const Node& n = tree.nodes[k];
    if (types[k] < 0 || n.children.size() != 2) continue;
    for (std::size_t side = 0; side < 2; ++side) {
      negated.at(static_cast<std::size_t>(n.children[side])) =
          kNeg[static_cast<std::size_t>(types[k])][1 + side];
    }
  }
  std::vector<int> out(tree.nodes.size(), -1);
  for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
    if (types[k] >= 0) out[k] = kNeg[static_cast<std::size_t>(types[k])][0] != negated[k] ? 1 : 0;
  }
  return out;
}

}  // namespace fuzzycsg
