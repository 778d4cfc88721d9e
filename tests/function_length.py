#!/usr/bin/env python3
"""No function in a folder's C files (its subfolders included) over a number of lines (src/render: 150;
the frame reads as its stages, docs/architecture.md). A definition runs from
the first line of its signature (at column 0) to its closing brace at column
0. Prints the longest; exit 1 when one is over the limit.

usage: function_length.py DIR MAX_LINES"""
import glob
import os
import re
import sys

folder, limit = sys.argv[1], int(sys.argv[2])
found = []
for path in sorted(glob.glob(os.path.join(folder, "**", "*.c"), recursive=True)):
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        m = re.match(r"^(?!typedef|struct\b|enum\b|#|/\*| )[A-Za-z_][\w\s\*]*?\b(\w+)\s*\(", lines[i])
        if m and "=" not in lines[i].split("(")[0]:
            j = i
            while j < len(lines) and not lines[j].rstrip().endswith(("{", ";")):
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith("{"):
                k = j
                while k < len(lines) and not lines[k].startswith("}"):
                    k += 1
                found.append((k - i + 1, os.path.relpath(path, folder), m.group(1)))
                i = k
        i += 1
found.sort(reverse=True)
for n, f, name in found[:5]:
    print("%4d lines  %s %s" % (n, f, name))
over = [x for x in found if x[0] > limit]
for n, f, name in over:
    print("FAIL %s %s: %d lines, over %d" % (f, name, n, limit))
sys.exit(1 if over or not found else 0)
