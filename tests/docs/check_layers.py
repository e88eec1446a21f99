#!/usr/bin/env python3
"""The house's floors, checked: no folder includes a folder above it, and no files include each
other, directly or round a longer loop.

The order is the one docs/design.md and the README's layout give:
  libraries    common <- reach <- sph, farfield (side by side: neither includes the other)
               sph <- gnn <- train, infer; spill-sim's front sim/ over sph, reach and farfield
  sph/         core, boundary, neighbours, river, near_field, solvers, forces, scene,
               simulation, io, generation, app (a floor includes only floors listed before it)
  farfield/    flows, model, outputs, ensemble, then the forecast's own files at the top
  gnn/         data, runtime, graph, models, then training and eval (side by side)
Tests are above everything and are not checked. Usage: check_layers.py REPO_ROOT; exit 1 naming
each include that runs the wrong way, and each loop.
"""
import os
import re
import sys

# (folder, rank): a file in a folder of rank r may include folders of rank < r, or its own.
# Folders of equal rank are side by side: neither may include the other.
LAYERS = [
    ("common", 0), ("reach", 1),
    ("sph/core", 2), ("sph/boundary", 3), ("sph/neighbours", 4), ("sph/river", 5),
    ("sph/near_field", 6), ("sph/solvers", 7), ("sph/forces", 8), ("sph/scene", 9),
    ("sph/simulation", 10), ("sph/io", 11), ("sph/generation", 12), ("sph/app", 13),
    ("farfield/flows", 2), ("farfield/model", 3), ("farfield/outputs", 4), ("farfield/ensemble", 5),
    ("farfield", 6),
    ("gnn/data", 20), ("gnn/runtime", 20), ("gnn/graph", 21), ("gnn/models", 22),
    ("gnn/training", 23), ("gnn/eval", 23),
    ("sim", 30), ("train", 30), ("infer", 30),
]
# Libraries that stand side by side on reach/ although their ranks overlap: no arrow between them.
APART = [("sph", "farfield"), ("farfield", "gnn"), ("farfield", "train"), ("farfield", "infer"),
         ("train", "infer"), ("sim", "train"), ("sim", "infer"), ("sim", "gnn")]
SOURCE_ROOTS = ["common", "reach", "sph", "farfield", "gnn", "sim", "train", "infer"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(path):
    """The most specific folder of LAYERS that holds `path` (a repository path)."""
    best = None
    for folder, rank in LAYERS:
        if path.startswith(folder + "/") and (best is None or len(folder) > len(best[0])):
            best = (folder, rank)
    return best


def library(folder):
    return folder.split("/")[0]


def sources(root):
    for top in SOURCE_ROOTS:
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in names:
                if name.endswith((".h", ".cpp")):
                    yield os.path.relpath(os.path.join(folder, name), root)


def main(root):
    problems = []
    graph = {}
    files = sorted(sources(root))
    for path in files:
        with open(os.path.join(root, path), encoding="utf-8") as f:
            included = INCLUDE.findall(f.read())
        graph[path] = [i for i in included if os.path.exists(os.path.join(root, i))]
        here = layer_of(path)
        if here is None:
            problems.append(f"{path}: in no layer of tests/docs/check_layers.py; add its folder")
            continue
        for target in graph[path]:
            there = layer_of(target)
            if there is None or there[0] == here[0]:
                continue
            a, b = library(here[0]), library(there[0])
            if (a, b) in APART or (b, a) in APART:
                problems.append(f"{path}: includes {target}, but {a}/ and {b}/ stand apart")
            elif there[1] >= here[1]:
                problems.append(f"{path}: includes {target}, a folder not below {here[0]}/")
    # Loops between files (a file's header and its .cpp are one node: the .cpp includes its .h).
    state = {}

    def visit(node, stack):
        state[node] = 1
        stack.append(node)
        for nxt in graph.get(node, []):
            if state.get(nxt) == 1:
                problems.append("include loop: " + " -> ".join(stack[stack.index(nxt):] + [nxt]))
            elif nxt not in state:
                visit(nxt, stack)
        stack.pop()
        state[node] = 2

    sys.setrecursionlimit(10000)
    for path in files:
        if path not in state:
            visit(path, [])
    for p in problems:
        print("check_layers:", p)
    edges = sum(len(v) for v in graph.values())
    print(f"check_layers: {len(files)} files, {edges} includes of project files checked, "
          f"{len(problems)} wrong")
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: check_layers.py REPO_ROOT", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
