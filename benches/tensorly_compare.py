#!/usr/bin/env python3
"""Issue 5 §3: TensorLy's parafac on the same tensor, rank and tolerance as ours.

Usage: tensorly_compare.py TENSOR.json RANK TOL MAX_ITERS
TENSOR.json: {"shape": [n0, n1, n2], "data": [...]} with index i + n0*(j + n1*k).
Prints one JSON line {"rel_error": ..., "seconds": ...}. Exits 3 with a message on
stderr when numpy or tensorly is missing (the Rust test then skips).
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
    with open(path) as f:
        t = json.load(f)
    n0, n1, n2 = t["shape"]
    x = np.asarray(t["data"], dtype=np.float64).reshape((n2, n1, n0)).transpose(2, 1, 0)
    start = time.perf_counter()
    cp = parafac(tl.tensor(x), rank=rank, n_iter_max=iters, tol=tol, init="random", random_state=0)
    seconds = time.perf_counter() - start
    rec = tl.cp_to_tensor(cp)
    err = float(np.linalg.norm(rec - x) / np.linalg.norm(x))
    print(json.dumps({"rel_error": err, "seconds": seconds}))


if __name__ == "__main__":
    main()
