#!/usr/bin/env python3
"""Checks that the manual's account of the core's layers is the build's.

The build declares the layers in core/CMakeLists.txt, bottom first:
fibrodem_layer(NAME [USES LAYER...]). docs/dev/layers.md's table ("| `NAME` |
... | uses |") must list the same layers in the same order with the same
uses ("-" for none), and docs/dev/architecture.md's folder layout the same
core/NAME/ lines in the same order.

Usage: scripts/check_docs_layers.py [REPO_ROOT]
Exit status 0 when they agree, 1 otherwise, naming each difference.
"""
import os
import re
import sys


def build_layers(root):
    text = open(os.path.join(root, "core", "CMakeLists.txt")).read()
    layers = []
    for name, uses in re.findall(r"^fibrodem_layer\((\w+)(?:\s+USES\s+([\w\s]+))?\)", text, re.M):
        layers.append((name, sorted((uses or "").split())))
    return layers


def table_layers(root):
    layers = []
    for line in open(os.path.join(root, "docs", "dev", "layers.md")):
        m = re.match(r"\|\s*`(\w+)`\s*\|.*\|\s*([^|]*?)\s*\|\s*$", line)
        if m:
            uses = [] if m.group(2) == "-" else sorted(u.strip() for u in m.group(2).split(","))
            layers.append((m.group(1), uses))
    return layers


def layout_layers(root):
    return re.findall(r"^core/(\w+)/", open(os.path.join(root, "docs", "dev", "architecture.md")).read(), re.M)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    build = build_layers(root)
    problems = []
    if not build:
        problems.append("core/CMakeLists.txt: no fibrodem_layer() found")
    table = table_layers(root)
    if table != build:
        problems.append("docs/dev/layers.md's table %s differs from core/CMakeLists.txt's layers %s" % (table, build))
    layout = layout_layers(root)
    if layout != [name for name, _ in build]:
        problems.append("docs/dev/architecture.md lists core/ as %s, the build as %s" % (layout, [n for n, _ in build]))
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
