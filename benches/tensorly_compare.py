#!/usr/bin/env python3
"""TensorLy's parafac on the same tensor, rank and tolerance as ours.

Usage: tensorly_compare.py TENSOR.json RANK TOL MAX_ITERS [REPEATS]
TENSOR.json: {"shape": [n0, n1, n2], "data": [...], "init": [A, B, C]} with data index
i + n0*(j + n1*k) and each init factor row-major (n_m x RANK): the start ndfbench's ALS
uses, so both run from the same factors ("init" absent: TensorLy's seeded random start).
Runs parafac REPEATS times (default 1) from that start and
prints one JSON line {"rel_error", "iterations", "seconds" (the fastest run), "version"}.
The convergence rule is TensorLy's default, cvg_criterion="abs_rec_error": stop when the
relative reconstruction error changes by less than TOL, which is the rule ndfbench uses.
Exits 3 with a message on stderr when numpy or tensorly is missing (callers then skip).
The caller sets OMP/OPENBLAS/MKL_NUM_THREADS=1 so both sides run on one core.
"""
import json
import sys
import time

try:
    import numpy as np
    import tensorly as tl
    from tensorly.decomposition import parafac
except ImportError as e:  # pragma: no cover - depends on the machine
    print(f"skipping TensorLy comparison: {e}", file=sys.stderr)
    sys.exit(3)


def main():
    path, rank, tol, iters = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
    repeats = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    with open(path) as f:
        t = json.load(f)
    n0, n1, n2 = t["shape"]
    x = np.asarray(t["data"], dtype=np.float64).reshape((n2, n1, n0)).transpose(2, 1, 0).copy()
    xt = tl.tensor(x)
    if "init" in t:
        factors = [np.asarray(f, dtype=np.float64).reshape((n, rank))
                   for f, n in zip(t["init"], (n0, n1, n2))]
        init = tl.cp_tensor.CPTensor((np.ones(rank), factors))
    else:
        init = "random"
    best = float("inf")
    for _ in range(max(repeats, 1)):
        start = time.perf_counter()
        cp, errors = parafac(xt, rank=rank, n_iter_max=iters, tol=tol, init=init,
                             random_state=0, return_errors=True)
        best = min(best, time.perf_counter() - start)
    rec = tl.cp_to_tensor(cp)
    err = float(np.linalg.norm(rec - x) / np.linalg.norm(x))
    print(json.dumps({"rel_error": err, "iterations": len(errors), "seconds": best,
                      "version": tl.__version__}))


if __name__ == "__main__":
    main()
