#!/usr/bin/env python3
"""The crate's layering, checked: import cycles, imports against the layer order, file sizes.

Reads every `crate::<module>` path in src/ (use lines and inline paths), maps each file to its
top-level module (src/<m>.rs or src/<m>/…), and prints
- the strongly connected components with more than one module, with the edges that close them
  (file:line of one use per edge);
- every import of a later layer than the importing one (LAYERS, as docs/architecture.md states it);
- every source file longer than MAX_LINES.
Exit status 1 when any of these is found, 0 when the layers depend one way. .ci/run runs it.

    python3 tools/module_cycles.py [SRC_DIR]
"""
import pathlib
import re
import sys

SRC = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "src")
# The layers in order: a module may import only from modules before it (docs/architecture.md).
LAYERS = ["error", "numerics", "model", "filter", "analysis", "families", "sim", "config", "pipeline", "report"]
MAX_LINES = 500
PATH = re.compile(r"\bcrate::([a-z_][a-z0-9_]*)")
# `use crate::{a, b::c}` names several modules at once.
GROUP = re.compile(r"\bcrate::\{([^}]*)\}", re.S)


def top_module(f: pathlib.Path) -> str | None:
    rel = f.relative_to(SRC).parts
    if rel[0] in ("main.rs", "lib.rs"):
        return None
    return rel[0][:-3] if rel[0].endswith(".rs") else rel[0]


def edges():
    out = {}
    for f in sorted(SRC.rglob("*.rs")):
        m = top_module(f)
        if m is None:
            continue
        # Doc links (`[crate::x]`) are not dependencies: comments are blanked, lines kept.
        text = "\n".join(re.sub(r"//.*", "", ln) for ln in f.read_text().split("\n"))
        found = [(x.start(), x.group(1)) for x in PATH.finditer(text)]
        for g in GROUP.finditer(text):
            for item in g.group(1).split(","):
                name = item.strip().split("::")[0].strip()
                if name and name != "self":
                    found.append((g.start(), name))
        for pos, target in found:
            if target != m and ((SRC / f"{target}.rs").exists() or (SRC / target).is_dir()):
                line = text.count("\n", 0, pos) + 1
                out.setdefault((m, target), f"{f}:{line}")
    return out


def sccs(nodes, adj):
    """Tarjan's algorithm, iterative enough for a crate's module graph."""
    index, low, stack, on, res, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in adj.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            res.append(sorted(comp))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return res


def main():
    e = edges()
    adj, nodes = {}, set()
    for a, b in e:
        adj.setdefault(a, set()).add(b)
        nodes |= {a, b}
    cycles = [c for c in sccs(nodes, adj) if len(c) > 1]
    for c in cycles:
        print(f"cycle of {len(c)} modules: {', '.join(c)}")
        for (a, b), where in sorted(e.items()):
            if a in c and b in c:
                print(f"  {a} -> {b}   ({where})")
    unknown = sorted(m for m in nodes if m not in LAYERS)
    for m in unknown:
        print(f"module `{m}` is in no layer: add it to LAYERS and docs/architecture.md")
    upward = sorted(
        (a, b, w) for (a, b), w in e.items() if a in LAYERS and b in LAYERS and LAYERS.index(b) > LAYERS.index(a)
    )
    for a, b, w in upward:
        print(f"layer `{a}` imports the later layer `{b}`   ({w})")
    long = [(f, n) for f in sorted(SRC.rglob("*.rs")) if (n := len(f.read_text().splitlines())) > MAX_LINES]
    for f, n in long:
        print(f"{f}: {n} lines (at most {MAX_LINES})")
    if cycles or unknown or upward or long:
        return 1
    print(f"no import cycle between the {len(nodes)} top-level modules; every import goes down the layers "
          f"{' → '.join(LAYERS)}; no source file over {MAX_LINES} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
