#!/usr/bin/env python3
"""The include graph between the core's folders (docs/dev/layers.md).

Reads every `#include "folder/..."` line of core/**/*.{hpp,cpp} and prints,
per pair of folders, how many include lines go from one to the other (with
one example), then the cycles (strongly connected components of more than one
folder) and, when there are none, the folders in an order where each comes
after everything it includes.

  scripts/include_graph.py [--dot] [CORE_DIR]   (default: core)

--dot prints the graph in Graphviz's dot language instead. Exits 1 when the
graph has a cycle.
"""
import re
import sys
from collections import defaultdict
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"([A-Za-z0-9_]+)/[^"]+"')


def folder_edges(core: Path):
    """{(from, to): [file:line, ...]} over the core's own folders."""
    folders = {p.name for p in core.iterdir() if p.is_dir()}
    edges = defaultdict(list)
    for source in sorted(core.rglob("*")):
        if source.suffix not in (".hpp", ".cpp", ".h") or not source.is_file():
            continue
        origin = source.relative_to(core).parts[0]
        if origin not in folders:
            continue
        for number, line in enumerate(source.read_text(errors="replace").splitlines(), 1):
            match = INCLUDE.match(line)
            if match and match.group(1) in folders and match.group(1) != origin:
                edges[(origin, match.group(1))].append(f"{source.relative_to(core)}:{number}")
    return folders, edges


def strongly_connected(nodes, successors):
    """Tarjan's algorithm; components in reverse topological order."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(successors[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            components.append(sorted(component))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return components


def main(argv):
    dot = "--dot" in argv
    args = [a for a in argv if a != "--dot"]
    core = Path(args[0] if args else "core")
    if not core.is_dir():
        sys.exit(f"include_graph: {core} is not a folder")
    folders, edges = folder_edges(core)
    successors = defaultdict(set)
    for (a, b) in edges:
        successors[a].add(b)
    components = strongly_connected(folders, successors)
    cycles = [c for c in components if len(c) > 1]

    if dot:
        print("digraph core {")
        for (a, b), sites in sorted(edges.items()):
            print(f'  "{a}" -> "{b}" [label="{len(sites)}"];')
        print("}")
        return 1 if cycles else 0

    print("Include lines between the core's folders (from -> to: lines, first site):")
    for (a, b), sites in sorted(edges.items()):
        print(f"  {a:>9} -> {b:<9} {len(sites):3d}  {sites[0]}")
    if cycles:
        print("Cycles (folders that include each other, directly or not):")
        for c in cycles:
            inner = [f"{a}->{b}" for (a, b) in sorted(edges) if a in c and b in c]
            print(f"  {{{', '.join(c)}}}: {' '.join(inner)}")
        return 1
    # Tarjan returns the components dependencies first.
    print("No cycles. Folders, each after what it includes:")
    print("  " + " < ".join(c[0] for c in components))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
