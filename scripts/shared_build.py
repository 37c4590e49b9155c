#!/usr/bin/env python3
"""Checks that the README's commands share one build of the dependencies.

cargo enables a dependency's features per command: `cargo run -p contactdd-cli` (the quick start),
`cargo test --workspace` (the tests, with criterion's graph) and maturin's build of the Python
module (numpy's graph) each resolve their own feature sets, and a crate built with different
features, or on top of one that was, is built again: faer, rayon and nalgebra three times. The
workspace Cargo.toml names the union through contactdd-core; this script fails, naming the crates,
when a dependency change makes the sets differ again.

Proc-macro helpers (syn) are built for the host, small, and exempt.
"""
import subprocess
import sys

COMMANDS = {
    "quick start": ["-e", "normal,build", "-p", "contactdd-cli"],
    "tests": ["-e", "normal,build,dev", "--workspace", "--exclude", "contactdd-python"],
    "python": ["-e", "normal,build", "-p", "contactdd-python"],
}
EXEMPT = {"syn"}


def features(args):
    """(crate, version) -> feature set, from `cargo tree`."""
    out = subprocess.run(
        ["cargo", "tree", "--locked", "--prefix", "none", "-f", "{p} {f}", *args],
        check=True, capture_output=True, text=True,
    ).stdout
    sets = {}
    for line in out.splitlines():
        parts = line.replace(" (*)", "").split()
        if len(parts) < 2 or parts[0].startswith("contactdd"):
            continue
        feats = set(parts[2].split(",")) if len(parts) > 2 and not parts[2].startswith("(") else set()
        sets.setdefault((parts[0], parts[1]), set()).update(feats)
    return sets


def main():
    graphs = {name: features(args) for name, args in COMMANDS.items()}
    differ = []
    for key in sorted(set().union(*graphs.values())):
        seen = {name: g[key] for name, g in graphs.items() if key in g}
        if key[0] not in EXEMPT and len(seen) > 1 and len({frozenset(f) for f in seen.values()}) > 1:
            differ.append(f"  {key[0]} {key[1]}: " + "; ".join(
                f"{name} [{','.join(sorted(f))}]" for name, f in seen.items()))
    if differ:
        print("the build commands enable different features (add the union to the workspace "
              "Cargo.toml's shared-build list):\n" + "\n".join(differ))
        return 1
    print(f"shared build: {len(set().union(*graphs.values()))} dependencies, one feature set each")
    return 0


if __name__ == "__main__":
    sys.exit(main())
