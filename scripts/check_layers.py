#!/usr/bin/env python3
"""Checks docs/design.md's layer rule: dependencies run one way.

  check_layers.py SRC_DIR [OBJECT_DIR]

1. Folders: folder A uses folder B when a file of A includes a header of B. The folders' graph
   must have no cycle.
2. Files (with OBJECT_DIR, the library's object files): file A uses file B when A's object has an
   undefined symbol that B's object defines (nm). Inside a folder too, no cycle: shared helpers
   live in the lowest file (the folder's internal header declares them).

Prints each cycle found, one line, and exits 1; exits 0 when there is none.
"""
import collections
import os
import re
import subprocess
import sys


def find_cycle(graph):
    """One cycle of the graph as a list of nodes, or None (iterative DFS, three colours)."""
    colour = {}
    for start in sorted(graph):
        if colour.get(start):
            continue
        stack = [(start, iter(sorted(graph.get(start, ()))))]
        colour[start] = 1
        path = [start]
        while stack:
            node, it = stack[-1]
            nxt = next(it, None)
            if nxt is None:
                colour[node] = 2
                stack.pop()
                path.pop()
            elif colour.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            elif not colour.get(nxt):
                colour[nxt] = 1
                stack.append((nxt, iter(sorted(graph.get(nxt, ())))))
                path.append(nxt)
    return None


def folder_graph(src):
    files = {}
    for d, _, names in os.walk(src):
        for n in names:
            if n.endswith(('.c', '.h', '.cpp')):
                rel = os.path.relpath(os.path.join(d, n), src)
                with open(os.path.join(d, n), encoding='utf-8', errors='replace') as f:
                    files[rel] = re.findall(r'#\s*include\s+"([^"]+)"', f.read())
    graph = collections.defaultdict(set)
    for rel, incs in files.items():
        for inc in incs:
            a, b = os.path.dirname(rel) or '.', os.path.dirname(inc) or '.'
            if inc in files and a != b:
                graph[a].add(b)
    return graph


def object_graph(objdir):
    objs = []
    for d, _, names in os.walk(objdir):
        objs += [os.path.join(d, n) for n in names if n.endswith('.o')]
    defs, uses = {}, collections.defaultdict(set)
    for o in objs:
        unit = os.path.relpath(o, objdir)
        unit = re.sub(r'\.(c|cpp)\.o$', '', unit)
        out = subprocess.run(['nm', o], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            parts = line.split()
            if len(parts) == 3 and parts[1] in 'TDBR':
                defs[parts[2]] = unit
            elif len(parts) == 2 and parts[0] == 'U':
                uses[unit].add(parts[1])
    graph = collections.defaultdict(set)
    for a, syms in uses.items():
        for s in syms:
            b = defs.get(s)
            if b and b != a:
                graph[a].add(b)
    return graph


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    bad = 0
    cycle = find_cycle(folder_graph(sys.argv[1]))
    if cycle:
        print('layers: the folders include each other in a cycle: ' + ' -> '.join(cycle))
        bad = 1
    if len(sys.argv) == 3:
        if not os.path.isdir(sys.argv[2]):
            print('layers: %s: no such folder of object files' % sys.argv[2])
            return 2
        cycle = find_cycle(object_graph(sys.argv[2]))
        if cycle:
            print('layers: the files call each other in a cycle: ' + ' -> '.join(cycle))
            bad = 1
    if not bad:
        print('layers: no cycle')
    return bad


if __name__ == '__main__':
    sys.exit(main())
