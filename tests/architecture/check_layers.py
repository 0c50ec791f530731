#!/usr/bin/env python3
"""The tree's shape, held as a test (Architecture.TheLayersAreKept):

    check_layers.py --repo ROOT

Reads every project-local #include of base/, compiler/, stdlib/, runtime/, apps/ and python/
(tests, bench and examples are users, not layers) and fails, naming the files, when:
  - a file includes a file of a layer above its own. The layers, lowest first:
      base < stdlib < compiler < runtime < apps, python
    (stdlib/guidance is pure image code: it includes nothing of the project); runtime/distributed
    is the only runtime folder that may link MPI (<mpi.h>), and nothing in runtime/ outside it
    includes it;
  - the includes make a cycle, between files or between folders;
  - apps/ holds more than 2,500 lines, or its includes of its own files nest deeper than 4 levels
    (the tool is flag handling; the work is in the library);
  - apps/ names MPI: distribution is runtime/distributed's.
Python 3, standard library only.
"""
import argparse
import collections
import os
import re
import sys

TOPS = ["base", "stdlib", "compiler", "runtime", "apps", "python"]
RANK = {"base": 0, "stdlib": 1, "compiler": 2, "runtime": 3, "apps": 4, "python": 4}
APPS_MAX_LINES = 2500
APPS_MAX_DEPTH = 4
INCLUDE = re.compile(r'^\s*#\s*include\s+([<"])([^">]+)[">]', re.M)
SOURCE = (".h", ".hpp", ".cpp")


def read_tree(root):
    files = {}
    for top in TOPS:
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in names:
                if name.endswith(SOURCE):
                    path = os.path.join(folder, name)
                    with open(path, encoding="utf-8", errors="replace") as f:
                        files[os.path.relpath(path, root)] = f.read()
    return files


def include_graph(files):
    """File -> the project files it includes (by root-relative or file-relative path)."""
    edges = collections.defaultdict(set)
    system = collections.defaultdict(set)
    for path, text in files.items():
        for quote, name in INCLUDE.findall(text):
            if quote == "<":
                system[path].add(name)
                continue
            for candidate in (name, os.path.normpath(os.path.join(os.path.dirname(path), name))):
                if candidate in files:
                    edges[path].add(candidate)
                    break
    return edges, system


def cycles(nodes, edges):
    """Strongly connected components with more than one member (Tarjan, iterative)."""
    index, low, on, stack, found, counter = {}, {}, set(), [], [], [0]
    for start in nodes:
        if start in index:
            continue
        work = [(start, iter(sorted(edges.get(start, ()))))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            v, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                    advanced = True
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def nesting(path, edges, within, memo):
    """How many levels of includes of `within`'s own files start at `path` (itself counted)."""
    if path not in memo:
        memo[path] = 0  # a cycle is reported elsewhere; it must not recurse forever here
        memo[path] = 1 + max((nesting(q, edges, within, memo) for q in edges.get(path, ()) if q.startswith(within)), default=0)
    return memo[path]


def check(root):
    files = read_tree(root)
    edges, system = include_graph(files)
    problems = []
    top = lambda p: p.split(os.sep)[0]
    for a in sorted(edges):
        for b in sorted(edges[a]):
            if RANK[top(b)] > RANK[top(a)] or (top(a) != top(b) and RANK[top(a)] == RANK[top(b)]):
                problems.append(f"{a} includes {b}: {top(b)}/ is not below {top(a)}/")
    for path in sorted(system):
        if "mpi.h" in system[path] and not path.startswith("runtime/distributed/"):
            problems.append(f"{path} includes <mpi.h>: only runtime/distributed/ links MPI")
    for component in cycles(sorted(files), edges):
        problems.append("include cycle between files: " + " -> ".join(component))
    folder_edges = collections.defaultdict(set)
    for a, bs in edges.items():
        for b in bs:
            if os.path.dirname(a) != os.path.dirname(b):
                folder_edges[os.path.dirname(a)].add(os.path.dirname(b))
    folders = sorted(set(folder_edges) | {b for bs in folder_edges.values() for b in bs})
    for component in cycles(folders, folder_edges):
        problems.append("include cycle between folders: " + ", ".join(component))
    apps = [p for p in files if top(p) == "apps"]
    lines = sum(files[p].count("\n") for p in apps)
    if lines > APPS_MAX_LINES:
        problems.append(f"apps/ holds {lines} lines, over {APPS_MAX_LINES}: move the work into the library")
    memo = {}
    depth = max((nesting(p, edges, "apps" + os.sep, memo) for p in apps), default=0)
    if depth > APPS_MAX_DEPTH:
        deepest = max(apps, key=lambda p: memo.get(p, 0))
        problems.append(f"apps/ nests its own includes {depth} levels deep from {deepest}, over {APPS_MAX_DEPTH}")
    mpi = re.compile(r"\bMPI_[A-Z]|\bmpi\.h\b|find_package\(MPI")
    for p in sorted(apps) + sorted(os.path.relpath(os.path.join(d, n), root) for d, _, ns in os.walk(os.path.join(root, "apps"))
                                   for n in ns if n == "CMakeLists.txt"):
        text = files.get(p) or open(os.path.join(root, p), encoding="utf-8").read()
        if mpi.search(text):
            problems.append(f"{p} names MPI: distribution belongs in runtime/distributed/")
    return problems, len(files), sum(len(b) for b in edges.values()), lines, depth


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repo", required=True)
    args = ap.parse_args()
    problems, n_files, n_edges, lines, depth = check(args.repo)
    for p in problems:
        print("error:", p, file=sys.stderr)
    print(f"{n_files} files, {n_edges} project includes; apps/ {lines} lines, nested {depth} deep; "
          f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
