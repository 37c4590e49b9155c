"""Size and write time of each VTU encoding on examples/notch.toml with its meshes refined.

Solves the notch once (nx × ny cells per body, 1000 × 500 by default: 1e6 DOFs per body), then
writes the result folder with each encoding `--repeat` times, alternating the encodings, and
prints, per encoding, the total size of the .vtu files and the median and range of the folder's
write time (Result.write_vtu: every .vtu file plus summary.json, contact.csv, history.csv and
results.pvd, which are the same for every encoding and small). Needs the contactdd Python module.
The last lines are the rows of the table in docs/outputs.md ("VTU encodings").

    python scripts/vtu_encodings.py [--nx 1000] [--ny 500] [--repeat 3]
"""

import argparse
import re
import statistics
import tempfile
import time
from pathlib import Path

import contactdd

ENCODINGS = ["ascii", "binary", "zlib"]
ROOT = Path(__file__).resolve().parent.parent


def refined_notch(nx: int, ny: int) -> contactdd.Problem:
    text = (ROOT / "examples" / "notch.toml").read_text()
    text = re.sub(r"nx = \d+, ny = \d+", f"nx = {nx}, ny = {ny}", text)
    return contactdd.Problem.from_toml_str(text, base_dir=ROOT / "examples", source="notch.toml")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nx", type=int, default=1000)
    parser.add_argument("--ny", type=int, default=500)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    start = time.perf_counter()
    result = contactdd.solve(refined_notch(args.nx, args.ny))
    print(f"notch {args.nx}x{args.ny} per body: solved in {time.perf_counter() - start:.1f} s "
          f"({sum(2 * len(b.nodes) for b in result.bodies)} DOFs)")
    times = {e: [] for e in ENCODINGS}
    sizes = {}
    with tempfile.TemporaryDirectory(prefix="vtu-encodings-") as tmp:
        for _ in range(args.repeat):
            for encoding in ENCODINGS:
                folder = Path(tmp) / encoding
                start = time.perf_counter()
                result.write_vtu(folder, format=encoding)
                times[encoding].append(time.perf_counter() - start)
                sizes[encoding] = sum(p.stat().st_size for p in folder.glob("*.vtu"))
    ascii_size = sizes["ascii"]
    print(f"{'encoding':<10} {'VTU bytes':>14} {'vs ascii':>9} {'write s (median)':>17} "
          f"{'min':>7} {'max':>7}")
    for encoding in ENCODINGS:
        t = times[encoding]
        print(f"{encoding:<10} {sizes[encoding]:>14,} {sizes[encoding] / ascii_size:>9.3f} "
              f"{statistics.median(t):>17.2f} {min(t):>7.2f} {max(t):>7.2f}")
    print()
    for encoding in ENCODINGS:
        t = times[encoding]
        print(f"| `{encoding}` | {sizes[encoding]:,} | {sizes[encoding] / ascii_size:.3f} | "
              f"{statistics.median(t):.2f} s ({min(t):.2f}–{max(t):.2f}) |")


if __name__ == "__main__":
    main()
