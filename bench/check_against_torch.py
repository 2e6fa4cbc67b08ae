#!/usr/bin/python3
"""Cross-checks the fuzzycsg evaluator's forward+backward against PyTorch autograd.

`eval_bench --dump-case FILE` builds a full binary tree of quadrics with unified operators
(make_full_binary_tree, the trees the benchmark times), evaluates occupancy, MSE loss and
gradient with the evaluator, and writes everything to FILE (JSON):
  format "fuzzycsg-bench-case", version 1
  params [..]              the tree's parameter vector (table order); param_names, fixed [bool]
  nodes [..], root         {"kind":"quadric","coefficients":[10 param indices],"sharpness":i}
                           {"kind":"unified","children":[a,b],"logits":[4 param indices],
                            "temperature":{"param":i}|{"value":v},"omega":{...}}
                           coefficients in the order of "monomials" (x², y², z², xy, yz, zx,
                           x, y, z, 1); x = children[0], y = children[1]
  points [N*3], targets [N]
  fuzzycsg {"loss", "grad" [per parameter], "occupancy" [per point], "threads"}
This script rebuilds the same model from that file in PyTorch (torch_model.case_loss_and_grad:
the layer-by-layer model the benchmark times, parameters gathered from the vector), in float64
as the reference and in float32 for scale, and compares:
  occupancy  max |o - o_ref|                                    <= 1e-5 (absolute)
  loss       |L - L_ref| / L_ref                                  <= 1e-5
  gradient   per group (leaf coefficients, sharpness, operator logits, other free parameters):
             max_i |g_i - ref_i| / max_i |ref_i|  (normwise)       <= 1e-4
             and every component |g_i - ref_i| <= 1e-3 |ref_i| + 1e-5 max |ref|
  fixed parameters: gradient exactly 0
It prints one line per quantity (error, tolerance, verdict) and exits 1 if any check fails.

  /usr/bin/python3 bench/check_against_torch.py [--eval-bench build/release/bench/eval_bench]
      [--P 64] [--N 2048] [--seed 1] [--threads 2] [--case FILE (skip eval_bench)] [--keep FILE]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import torch_model  # noqa: E402

OCC_ATOL = 1e-5
LOSS_RTOL = 1e-5
GRAD_NORMWISE = 1e-4
GRAD_RTOL = 1e-3
GRAD_ATOL_REL = 1e-5


def parameter_groups(case):
    """Parameter indices by role, free parameters only (fixed ones are checked separately)."""
    fixed = case["fixed"]
    groups = {"leaf coefficients": set(), "leaf sharpness": set(), "operator logits": set()}
    for node in case["nodes"]:
        if node["kind"] == "quadric":
            groups["leaf coefficients"].update(node["coefficients"])
            groups["leaf sharpness"].add(node["sharpness"])
        else:
            groups["operator logits"].update(node["logits"])
    assigned = set().union(*groups.values())
    groups["other"] = set(range(len(case["params"]))) - assigned
    return {name: sorted(i for i in idx if not fixed[i]) for name, idx in groups.items() if idx}


def compare_grad(got, ref, idx):
    if not idx:
        return None
    g = torch.tensor([got[i] for i in idx], dtype=torch.float64)
    r = torch.tensor([ref[i] for i in idx], dtype=torch.float64)
    scale = r.abs().max().item()
    err = (g - r).abs()
    normwise = err.max().item() / scale if scale > 0 else err.max().item()
    componentwise = bool((err <= GRAD_RTOL * r.abs() + GRAD_ATOL_REL * scale).all())
    return {"n": len(idx), "scale": scale, "max_abs": err.max().item(), "normwise": normwise,
            "componentwise_ok": componentwise,
            "ok": normwise <= GRAD_NORMWISE and componentwise}


def report(label, case, result, ref, groups):
    ok = True
    lines = []
    occ = torch.tensor(result["occupancy"], dtype=torch.float64)
    occ_ref = torch.tensor(ref["occupancy"], dtype=torch.float64)
    occ_err = (occ - occ_ref).abs().max().item()
    passed = occ_err <= OCC_ATOL
    ok &= passed
    lines.append(f"  occupancy ({len(occ)} points): max abs err {occ_err:.2e} "
                 f"(tol {OCC_ATOL:.0e}) {'ok' if passed else 'FAIL'}")
    loss_err = abs(result["loss"] - ref["loss"]) / abs(ref["loss"])
    passed = loss_err <= LOSS_RTOL
    ok &= passed
    lines.append(f"  loss {result['loss']:.9g} vs {ref['loss']:.9g}: rel err {loss_err:.2e} "
                 f"(tol {LOSS_RTOL:.0e}) {'ok' if passed else 'FAIL'}")
    for name, idx in groups.items():
        c = compare_grad(result["grad"], ref["grad"], idx)
        if c is None:
            continue
        ok &= c["ok"]
        lines.append(
            f"  grad {name} ({c['n']}): max |ref| {c['scale']:.3e}, max abs err "
            f"{c['max_abs']:.2e}, normwise rel err {c['normwise']:.2e} (tol {GRAD_NORMWISE:.0e}), "
            f"componentwise {'ok' if c['componentwise_ok'] else 'FAIL'} -> "
            f"{'ok' if c['ok'] else 'FAIL'}")
    fixed = [i for i, f in enumerate(case["fixed"]) if f]
    if fixed:
        nonzero = [i for i in fixed if result["grad"][i] != 0.0]
        passed = not nonzero or label.startswith("torch")
        ok &= passed
        if label.startswith("torch"):
            lines.append(f"  fixed parameters ({len(fixed)}): not applicable to autograd")
        else:
            lines.append(f"  fixed parameters ({len(fixed)}): {len(nonzero)} nonzero gradients "
                         f"{'ok' if passed else 'FAIL'}")
    if label.startswith("torch"):
        print(f"{label}: within the same tolerances: {'yes' if ok else 'no'}")
    else:
        print(f"{label}: {'AGREES' if ok else 'DISAGREES'}")
    print("\n".join(lines))
    return ok


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--eval-bench",
                    default=os.path.join(here, "..", "build", "release", "bench", "eval_bench"))
    ap.add_argument("--case", help="an existing case file (do not run eval_bench)")
    ap.add_argument("--P", type=int, default=64)
    ap.add_argument("--N", type=int, default=2048)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--keep", help="keep the case file here")
    args = ap.parse_args(argv)

    path = args.case
    if path is None:
        path = args.keep or os.path.join(tempfile.mkdtemp(prefix="fuzzycsg-case-"), "case.json")
        cmd = [args.eval_bench, "--dump-case", path, "--case-P", str(args.P), "--case-N",
               str(args.N), "--seed", str(args.seed), "--threads", str(args.threads)]
        subprocess.run(cmd, check=True)
    with open(path) as f:
        case = json.load(f)
    if case.get("format") != "fuzzycsg-bench-case" or "fuzzycsg" not in case:
        sys.exit(f"{path}: not a case file with fuzzycsg results")
    if tuple(case["monomials"]) != torch_model.MONOMIALS:
        sys.exit(f"{path}: monomial order {case['monomials']} differs from the model's")

    groups = parameter_groups(case)
    loss64, grad64, occ64 = torch_model.case_loss_and_grad(case, torch.float64)
    loss32, grad32, occ32 = torch_model.case_loss_and_grad(case, torch.float32)
    ref = {"loss": loss64, "grad": grad64, "occupancy": occ64}
    n = len(case["targets"])
    print(f"case {path}: P={case['leaves']} N={n} params={len(case['params'])} "
          f"seed={case['seed']} evaluator threads={case['fuzzycsg']['threads']}")
    print("reference: PyTorch autograd in float64 on the same tree, parameters and points")
    ok = report("fuzzycsg (float32 kernel) vs reference", case, case["fuzzycsg"], ref, groups)
    # PyTorch in float32 against the same reference: the error a float32 evaluation makes. With
    # t = 1000, float32 rounding of sin(omega * logits) * t alone moves c by ~1e-4 relative, so
    # the logit gradients of an all-float32 evaluation sit near the tolerance.
    report("torch float32 vs reference (for scale, not a check)", case,
           {"loss": loss32, "grad": grad32, "occupancy": occ32}, ref, groups)
    print("RESULT:", "fuzzycsg agrees with PyTorch autograd" if ok else "MISMATCH")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
