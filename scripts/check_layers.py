#!/usr/bin/env python3
"""Checks that no library header or source includes one from a higher layer (docs/architecture.md).

The layer of a file is the first folder under include/sets/ or src/ (methods/<paper> for a method).
A file may include its own layer and the layers below it; a method may not include another
method; nothing in the library includes `examples`, which only apps, tests and benches use.

    python3 scripts/check_layers.py            # exit 1 and one line per violation
    python3 scripts/check_layers.py --graph    # the layer graph as included today (for the docs)
    python3 scripts/check_layers.py --check-doc docs/architecture.md
        # also checks that the graph between the markers in the doc is the one the includes give
"""
import pathlib
import re
import sys

LAYERS = ["core", "numeric", "domains", "fps", "models", "data", "methods", "diagnosis", "examples"]
RANK = {name: i for i, name in enumerate(LAYERS)}
INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]([^>"]+)[>"]')
ROOT = pathlib.Path(__file__).resolve().parent.parent
BEGIN, END = "<!-- layer-graph:begin -->", "<!-- layer-graph:end -->"


def layer_of(parts):
    """('methods', 'tv_bound', 'x.hpp') -> 'methods/tv_bound'; ('fps', 'x.hpp') -> 'fps'."""
    if len(parts) < 2 or parts[0] not in RANK:
        return None
    return f"methods/{parts[1]}" if parts[0] == "methods" and len(parts) > 2 else parts[0]


def included_layer(target):
    parts = target.split("/")
    if parts[0] == "sets":  # public: sets/<layer>/...
        parts = parts[1:]
    return layer_of(parts)


def library_files():
    for base in ("include/sets", "src"):
        for path in sorted((ROOT / base).rglob("*")):
            if path.suffix in (".hpp", ".cpp", ".h") and path.is_file():
                rel = path.relative_to(ROOT / base)
                if rel.parts == ("sets.hpp",):
                    continue  # the umbrella header includes everything on purpose
                yield path, layer_of(rel.parts)


def allowed(src, dst):
    top_src, top_dst = src.split("/")[0], dst.split("/")[0]
    if top_src == "methods" and top_dst == "methods":
        return src == dst
    return RANK[top_dst] <= RANK[top_src]


def scan():
    violations, edges = [], {}
    for path, layer in library_files():
        if layer is None:
            violations.append(f"{path.relative_to(ROOT)}: not inside a layer folder ({', '.join(LAYERS)})")
            continue
        for lineno, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = included_layer(m.group(1))
            if target is None:
                continue  # a system or third-party header
            if target != layer:
                edges[(layer, target)] = edges.get((layer, target), 0) + 1
            if not allowed(layer, target):
                violations.append(f"{path.relative_to(ROOT)}:{lineno}: layer '{layer}' includes "
                                  f"'{m.group(1)}' from the higher or sibling layer '{target}'")
    return violations, edges


def graph_text(edges):
    """One line per layer, lowest first: the layers it includes (by top-level layer)."""
    uses = {}
    for (src, dst) in edges:
        s, d = src.split("/")[0], dst.split("/")[0]
        if s != d:
            uses.setdefault(s, set()).add(d)
    lines = []
    for name in reversed(LAYERS):
        below = sorted(uses.get(name, ()), key=RANK.get, reverse=True)
        lines.append(f"{name:<10} -> {', '.join(below) if below else '(nothing)'}")
    return "\n".join(lines)


def main(argv):
    violations, edges = scan()
    graph = graph_text(edges)
    if "--graph" in argv:
        print(graph)
        return 0
    if "--check-doc" in argv:
        doc = ROOT / argv[argv.index("--check-doc") + 1]
        text = doc.read_text()
        if BEGIN not in text or END not in text:
            violations.append(f"{doc}: no layer graph between {BEGIN} and {END}")
        else:
            block = text.split(BEGIN, 1)[1].split(END, 1)[0].strip().strip("`").strip()
            if block != graph:
                violations.append(f"{doc}: the layer graph is out of date; run "
                                  f"'python3 scripts/check_layers.py --graph' and paste:\n{graph}")
    for v in violations:
        print(v, file=sys.stderr)
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
