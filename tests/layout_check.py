#!/usr/bin/env python3
"""The house's layout (docs/architecture.md), checked from the includes:
- no room (a folder of src/) includes src/app, the command line above them;
- the rooms' include graph has no cycle, so each room builds on the ones
  below it (src/render is one room; its concern folders frame, scene,
  photon, estimate and filter share the frame's plan and targets);
- no header is part of an include cycle;
- src/render and shaders/ hold their files one level deeper by concern:
  at their top only render.h and the settings table, and no kernel.

usage: layout_check.py REPO_ROOT"""
import glob
import os
import re
import sys

from pbcheck import check as tally, finish


def check(ok, what, detail=None):
    return tally(ok, what + ("" if ok or not detail else ": " + str(detail)))

root = sys.argv[1]
src = os.path.join(root, "src")
INC = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def room_of(rel):
    return rel.split("/")[0]


files = {}
for path in glob.glob(os.path.join(src, "**", "*.*"), recursive=True):
    if path.endswith((".c", ".h", ".cpp")):
        rel = os.path.relpath(path, src)
        files[rel] = INC.findall(open(path, encoding="utf-8", errors="replace").read())

# 1. Nothing below the command line includes it.
up = sorted("%s -> %s" % (f, i) for f, incs in files.items() if not f.startswith("app/")
            for i in incs if i.startswith("app/"))
check(not up, "no room includes app/", "; ".join(up))

# 2. The rooms' graph is acyclic.
edges = {}
for f, incs in files.items():
    a = room_of(f)
    for i in incs:
        if i in files:
            b = room_of(i)
            if a != b:
                edges.setdefault(a, {}).setdefault(b, "%s -> %s" % (f, i))


def find_cycle(graph):
    state, stack = {}, []

    def visit(n):
        state[n] = 1
        stack.append(n)
        for m in sorted(graph.get(n, {})):
            if state.get(m) == 1:
                return stack[stack.index(m):] + [m]
            if not state.get(m):
                c = visit(m)
                if c:
                    return c
        stack.pop()
        state[n] = 2
        return None

    for n in sorted(graph):
        if not state.get(n):
            c = visit(n)
            if c:
                return c
    return None


cyc = find_cycle(edges)
check(cyc is None, "the rooms' include graph has no cycle (%d rooms)" % len({room_of(f) for f in files}),
      cyc and " -> ".join(cyc) + " (" + "; ".join(edges[cyc[k]][cyc[k + 1]] for k in range(len(cyc) - 1)) + ")")

# 3. No header include cycle.
hgraph = {f: {i: 1 for i in incs if i in files} for f, incs in files.items() if f.endswith(".h")}
cyc = find_cycle(hgraph)
check(cyc is None, "no header include cycle (%d headers)" % len(hgraph), cyc and " -> ".join(cyc))

# 4. One level deeper by concern.
top = sorted(os.path.basename(p) for p in glob.glob(os.path.join(src, "render", "*.*")))
check(top == ["render.h", "settings.c", "settings.h"], "src/render's top holds render.h and the settings table only",
      ", ".join(top))
kernels = sorted(os.path.basename(p) for p in glob.glob(os.path.join(root, "shaders", "*.comp")))
check(not kernels, "every kernel sits in a concern's folder of shaders/", ", ".join(kernels))
names = [os.path.basename(p) for p in glob.glob(os.path.join(root, "shaders", "*", "*.comp"))]
check(len(names) == len(set(names)) and len(names) > 40, "%d kernels, each name once" % len(names))
finish()
