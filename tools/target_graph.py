#!/usr/bin/env python3
"""Prints the project's library dependency graph, layer by layer.

Asks CMake for the graph of a configured build tree (cmake --graphviz) and
prints each Earshot library with the Earshot libraries it links directly,
lowest layer first (a library's layer is one above the highest it links).
Exits 1 if the libraries link in a cycle, 2 on bad arguments.

  tools/target_graph.py build/release           # the layers
  tools/target_graph.py build/release --dot      # Graphviz, for `dot -Tpng`
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

EDGE = re.compile(r'//\s*(\S+)\s*->\s*(\S+)\s*$')
NODE = re.compile(r'"(node\d+)"\s*\[\s*label\s*=\s*"([^"]+)",\s*shape\s*=\s*(\w+)')
LIBRARY_SHAPES = {"octagon", "doubleoctagon", "tripleoctagon", "hexagon"}


def read_graph(build):
    with tempfile.TemporaryDirectory() as tmp:
        dot = os.path.join(tmp, "g.dot")
        r = subprocess.run(["cmake", f"--graphviz={dot}", build], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"target_graph: cmake --graphviz on {build} failed:\n{r.stderr}")
        text = open(dot).read()
    # Labels read "name\\n(alias)" for targets with an alias: keep the name.
    shapes = {label.split("\\n")[0]: shape for _, label, shape in NODE.findall(text)}
    ours = {n for n, s in shapes.items() if s in LIBRARY_SHAPES and n.startswith("earshot")
            and "bench" not in n and n != "earshot_analysis"}
    deps = {n: set() for n in ours}
    for line in text.splitlines():
        m = EDGE.search(line)
        if m and m.group(1) in ours and m.group(2) in ours:
            deps[m.group(1)].add(m.group(2))
    return deps


def layers(deps):
    level, visiting = {}, set()

    def visit(n):
        if n in level:
            return level[n]
        if n in visiting:
            sys.stdout.write(f"cycle through {n}\n")
            sys.exit(1)
        visiting.add(n)
        level[n] = 1 + max((visit(d) for d in deps[n]), default=-1)
        visiting.discard(n)
        return level[n]

    for n in deps:
        visit(n)
    return level


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", help="a configured build tree, e.g. build/release")
    ap.add_argument("--dot", action="store_true", help="print Graphviz instead of the layers")
    a = ap.parse_args()
    if not os.path.isfile(os.path.join(a.build, "CMakeCache.txt")):
        print(f"target_graph: {a.build}: not a configured build tree (no CMakeCache.txt)", file=sys.stderr)
        return 2
    deps = read_graph(a.build)
    level = layers(deps)
    if a.dot:
        print("digraph earshot {\n  rankdir=BT;")
        for n in sorted(deps):
            for d in sorted(deps[n]):
                print(f'  "{n}" -> "{d}";')
        print("}")
        return 0
    for lv in range(max(level.values(), default=-1) + 1):
        for n in sorted(k for k, v in level.items() if v == lv):
            print(f"{lv}  {n:32} -> {', '.join(sorted(deps[n])) or '-'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
