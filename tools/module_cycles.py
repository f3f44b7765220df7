#!/usr/bin/env python3
"""The crate's layering, checked: import cycles at every depth, imports against the layer order,
file sizes.

A module is a source file's path without `.rs` (`a/mod.rs` is the module `a`, lib.rs the crate
root). Every path in src/ that names a module of the crate is a dependency of the file it is in:
`use` trees (groups `crate::x::{a, b::c}`, `self` in a group, renames), and paths in code,
starting with `crate::`, `super::`, `self::` or a child module's name. A path depends on the
deepest module it names (`crate::a::b::Item` on `a::b`, if `a/b.rs` or `a/b/mod.rs` exists); an
item a module re-exports (`pub use x::Item`) is followed to the module it comes from. Comments
(doc links included) and string literals are not dependencies.

The script prints, with one file:line per edge,
- every import cycle, at every depth: in each folder (src/ itself included), the graph whose nodes
  are the folder's own file (lib.rs, a mod.rs) and its sub-modules (a child folder counts as one
  node, with everything in it), with an edge whenever a file under one node uses a module under
  another. A cycle between two files shows in the folder whose children hold them, so none is
  missed; nor is a cycle between folders that no two single files close. The own file is a node
  like the others: a mod.rs that uses its children (declares a registry of them, dispatches to
  them) may not define what they use, which then lives in a leaf file of the folder that the
  mod.rs re-exports (`pub use`);
- every import of a later top-level layer than the importing one (LAYERS, as
  docs/architecture.md states it), and every top-level module in no layer;
- every source file longer than MAX_LINES.
Exit status 1 when any of these is found, 0 otherwise, 2 for an option (there is none) or a
SRC_DIR without Rust files. .ci/run runs it.

Not seen: a dependency that goes only through a glob re-export (`pub use x::*` read as `y::Item`
counts as a use of the re-exporting module), and a path through a `use` alias of a module.

    python3 tools/module_cycles.py [SRC_DIR]
"""
import pathlib
import re
import sys

ARGS = sys.argv[1:]
if len(ARGS) > 1 or any(a.startswith("-") for a in ARGS):
    # `--strict` is gone (a folder's own file is always a node); an option read as SRC_DIR would
    # check an empty tree and pass.
    print("usage: python3 tools/module_cycles.py [SRC_DIR]", file=sys.stderr)
    sys.exit(2)
SRC = pathlib.Path(ARGS[0] if ARGS else "src")
# The layers in order: a module may import only from modules before it (docs/architecture.md).
LAYERS = ["error", "numerics", "model", "filter", "analysis", "families", "sim", "config", "pipeline", "report", "verdict"]
MAX_LINES = 500
IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
# A path in code: `a::b::c`, not preceded by `::`, `$` (macro `$crate`) or an identifier character.
CODE_PATH = re.compile(rf"(?<![\w$:])(?:r#)?({IDENT}(?:\s*::\s*{IDENT})+)")
USE = re.compile(r"(?<![\w$])use\s")
USE_ITEM = re.compile(r"(?<![\w$])use\s[^;]*;")


def module_of(f: pathlib.Path):
    """The module a file is, as a tuple of names; None for main.rs (the binary, another crate)."""
    parts = f.relative_to(SRC).parts
    if parts == ("main.rs",) or parts[0] == "bin":
        return None
    if parts == ("lib.rs",):
        return ()
    if parts[-1] == "mod.rs":
        return tuple(parts[:-1])
    return tuple(parts[:-1]) + (parts[-1][:-3],)


def blank(text: str) -> str:
    """`text` with comments and string/char literals replaced by spaces, line breaks kept."""
    out, i, n = [], 0, len(text)

    def keep(s):
        return "".join(c if c == "\n" else " " for c in s)

    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(keep(text[i:j]))
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(keep(text[i:j]))
            i = j
        elif (m := re.match(r'b?r(#*)"', text[i:])) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            end = '"' + m.group(1)
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append(keep(text[i:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(keep(text[i : j + 1]))
            i = j + 1
        elif c == "'" and (m := re.match(r"'(\\.[^']*|[^\\'])'", text[i:])):
            # A char literal ('a', '\n', '\u{..}'), not a lifetime ('a without a closing quote).
            out.append(keep(m.group(0)))
            i += m.end()
        else:
            out.append(c)
            i += 1
    return "".join(out)


def line_of(text: str, pos: int) -> int:
    return text.count("\n", 0, pos) + 1


def use_leaves(tree: str, start: int):
    """The paths a `use` tree names, as (segments, position of the last segment) pairs.

    `a::{self, b::{c, d as e}, f::*}` gives a, a::b::c, a::b::d, a::f (a glob names its module)."""
    tokens = [(m.group(0), start + m.start()) for m in re.finditer(rf"::|{IDENT}|[{{}},*]", tree)]
    pos = [0]

    def parse(prefix):
        """One use tree at tokens[pos]: a path, then optionally `::{…}`, `::*` or `as x`."""
        segs, at = list(prefix), None
        while pos[0] < len(tokens):
            tok, p = tokens[pos[0]]
            if tok == "{":
                pos[0] += 1
                out = []
                while pos[0] < len(tokens) and tokens[pos[0]][0] != "}":
                    if tokens[pos[0]][0] == ",":
                        pos[0] += 1
                        continue
                    out += parse(segs)
                pos[0] += 1
                return out
            if tok == "*":
                pos[0] += 1
                return [(segs, p)]
            if tok in (",", "}"):
                break
            if tok == "as":
                pos[0] += 2
                break
            if tok != "::":
                if tok == "self" and prefix and segs == list(prefix):
                    pass  # `self` in a group: the group's module itself
                else:
                    segs.append(tok)
                at = p
            pos[0] += 1
        return [(segs, at)] if at is not None else []

    out = []
    while pos[0] < len(tokens):
        out += parse([])
        while pos[0] < len(tokens) and tokens[pos[0]][0] == ",":
            pos[0] += 1
    return out


class Crate:
    def __init__(self):
        self.files = {}  # module -> path
        for f in sorted(SRC.rglob("*.rs")):
            m = module_of(f)
            if m is not None:
                self.files[m] = f
        self.text = {m: blank(f.read_text()) for m, f in self.files.items()}
        self.reexports = {m: self._reexports(m) for m in self.files}

    def _uses(self, m):
        """(segments, position, is `pub use`) of every leaf of every `use` in module m."""
        text = self.text[m]
        for u in USE.finditer(text):
            end = text.find(";", u.end())
            if end < 0:
                continue
            public = re.search(r"pub(\s*\([^)]*\))?\s*$", text[max(0, u.start() - 40) : u.start()]) is not None
            for segs, p in use_leaves(text[u.end() : end], u.end()):
                yield segs, p, public

    def _reexports(self, m):
        """Item name -> the path it is re-exported from, for module m's `pub use … Item`."""
        out = {}
        for segs, _, public in self._uses(m):
            if public and segs:
                out[segs[-1]] = segs
        return out

    def absolute(self, m, segs):
        """`segs` (a path written in module m) as segments from the crate root, or None when it
        starts outside the crate (std, another crate, a local item)."""
        segs = [s for s in segs if s != ""]
        if not segs:
            return None
        head, rest = segs[0], segs[1:]
        if head == "crate":
            return rest
        if head in ("self", "super"):
            base = list(m)
            while segs and segs[0] in ("self", "super"):
                if segs[0] == "super":
                    if not base:
                        return None
                    base.pop()
                segs = segs[1:]
            return base + segs
        if m + (head,) in self.files:  # a child module, named relatively (Rust 2018 paths)
            return list(m) + segs
        return None

    def target(self, m, segs, seen=()):
        """The deepest module the path `segs` (written in m) names, following re-exports."""
        path = self.absolute(m, segs)
        if path is None:
            return None
        depth = max(d for d in range(len(path) + 1) if tuple(path[:d]) in self.files)
        t, rest = tuple(path[:depth]), path[depth:]
        if rest and rest[0] in self.reexports.get(t, {}) and (t, rest[0]) not in seen:
            via = self.target(t, self.reexports[t][rest[0]], seen + ((t, rest[0]),))
            if via is not None:
                return via
        return t

    def edges(self):
        """{(from module, to module): "file:line"} of the first use of each dependency."""
        out = {}
        for m in self.files:
            text, f = self.text[m], self.files[m]
            found = [(p, segs) for segs, p, _ in self._uses(m)]
            # Paths in code, with the `use` items (read whole above) blanked.
            code = USE_ITEM.sub(lambda u: re.sub(r"[^\n]", " ", u.group(0)), text)
            for x in CODE_PATH.finditer(code):
                found.append((x.start(), re.split(r"\s*::\s*", x.group(1))))
            for p, segs in sorted(found, key=lambda t: t[0]):
                t = self.target(m, segs)
                if t is not None and t != m:
                    out.setdefault((m, t), f"{f}:{line_of(text, p)}")
        return out


def name(mod):
    return "::".join(mod) if mod else "crate"


def folder_graphs(edges):
    """Per folder, its edges between nodes: its children and its own file ("")."""
    graphs = {}
    for (a, b), where in edges.items():
        k = 0
        while k < min(len(a), len(b)) and a[k] == b[k]:
            k += 1
        folder = a[:k]
        na = a[k] if len(a) > k else ""  # "": the folder's own file
        nb = b[k] if len(b) > k else ""
        graphs.setdefault(folder, {}).setdefault((na, nb), []).append((a, b, where))
    return graphs


def sccs(nodes, adj):
    """Tarjan's algorithm."""
    index, low, stack, on, res, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(adj.get(v, ()), key=str):
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
            res.append(comp)

    for v in sorted(nodes, key=str):
        if v not in index:
            visit(v)
    return res


def shortest_cycle(comp, adj):
    """A shortest cycle through the component's first node (breadth-first), as a node list."""
    start = sorted(comp, key=str)[0]
    prev, frontier = {start: None}, [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(adj.get(v, ()), key=str):
                if w not in comp:
                    continue
                if w == start:
                    path = [v]
                    while prev[path[-1]] is not None:
                        path.append(prev[path[-1]])
                    return path[::-1]
                if w not in prev:
                    prev[w] = v
                    nxt.append(w)
        frontier = nxt
    return [start]


def cycles(edges):
    """Printable reports of every cycle, folder by folder; empty when there is none."""
    out = []
    for folder, g in sorted(folder_graphs(edges).items()):
        adj = {}
        for a, b in g:
            adj.setdefault(a, set()).add(b)
        here = "src/" + "/".join(folder) + ("/" if folder else "")

        def label(node):
            return name(folder) + " (its own file)" if node == "" else name(folder + (node,))

        for comp in sccs({n for e in g for n in e}, adj):
            if len(comp) < 2:
                continue
            ring = shortest_cycle(set(comp), adj)
            lines = [f"cycle in {here}: {' -> '.join(label(n) for n in ring + [ring[0]])}"]
            used = set()
            for a, b in zip(ring, ring[1:] + ring[:1]):
                fa, fb, where = g[(a, b)][0]
                lines.append(f"  {name(fa)} -> {name(fb)}   ({where})")
                used.add((a, b))
            rest = sorted((k for k in g if k[0] in comp and k[1] in comp and k not in used), key=str)
            if rest:
                lines.append(f"  other edges among {', '.join(sorted(label(n) for n in comp))}:")
                for k in rest:
                    for fa, fb, where in g[k]:
                        lines.append(f"    {name(fa)} -> {name(fb)}   ({where})")
            out.append("\n".join(lines))
    return out


def main():
    if not SRC.is_dir() or not any(SRC.rglob("*.rs")):
        print(f"{SRC}: no Rust source files", file=sys.stderr)
        return 2
    crate = Crate()
    e = crate.edges()
    found = cycles(e)
    for c in found:
        print(c)
    # The top-level layers: every file maps to its top-level module.
    top = {}
    for (a, b), where in e.items():
        if a and b and a[0] != b[0]:
            top.setdefault((a[0], b[0]), where)
    nodes = {m[0] for m in crate.files if m}
    unknown = sorted(m for m in nodes if m not in LAYERS)
    for m in unknown:
        print(f"module `{m}` is in no layer: add it to LAYERS and docs/architecture.md")
    upward = sorted(
        (a, b, w) for (a, b), w in top.items() if a in LAYERS and b in LAYERS and LAYERS.index(b) > LAYERS.index(a)
    )
    for a, b, w in upward:
        print(f"layer `{a}` imports the later layer `{b}`   ({w})")
    long = [(f, n) for f in sorted(SRC.rglob("*.rs")) if (n := len(f.read_text().splitlines())) > MAX_LINES]
    for f, n in long:
        print(f"{f}: {n} lines (at most {MAX_LINES})")
    if found or unknown or upward or long:
        return 1
    folders = len({m[:-1] for m in crate.files if m}) if crate.files else 0
    print(
        f"no import cycle among the {len(crate.files)} modules ({len(e)} dependencies) in any of the "
        f"{folders} folders; every import goes down the layers {' → '.join(LAYERS)}; no source file over "
        f"{MAX_LINES} lines"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
