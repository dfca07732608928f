"""What the Python call adds over the Rust call: for each body, the time of
``trigbody.reconstruct(vertices, faces)`` against the time the library's
``reconstruct`` took inside the same call (``Report.seconds``); the rest is
the package's own work (numpy to the library's points, the model and the
report's JSON back). Measured in the same call, so a busy machine slows
both alike.

    python crates/py/bench/overhead.py [--reps 5] BODY [BODY ...]
"""

import argparse
import statistics
import time

import trigbody


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("bodies", nargs="+")
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--units", default="m")
    args = p.parse_args()
    shares = []
    for path in args.bodies:
        v, f, n = trigbody.read_geometry(path)
        rows = []
        for _ in range(args.reps):
            t0 = time.perf_counter()
            _, report = trigbody.reconstruct(v, f, normals=n, units=args.units)
            total = time.perf_counter() - t0
            rows.append((total, report.seconds))
        total = statistics.median(t for t, _ in rows)
        rust = statistics.median(s for _, s in rows)
        extra = statistics.median((t - s) / s for t, s in rows)
        shares.append(extra)
        print(f"{path}: {len(v)} vertices, python call {total:.3f} s, rust call {rust:.3f} s, "
              f"added {1000 * statistics.median(t - s for t, s in rows):.2f} ms ({100 * extra:.2f} %)")
    print(f"median added share over {len(shares)} bodies: {100 * statistics.median(shares):.2f} %")


if __name__ == "__main__":
    main()
