#!/usr/bin/env python3
"""The code's shape, measured: file-level import cycles per crate and the longest functions.

An import is any path into the crate in a file's non-test code (`use crate::a::B`,
`super::c::d()`, `crate::e::F` inline), resolved through re-exports (`pub use`) to the file
that defines the item. Files that import each other in a circle form a strongly connected
component; each one with more than one file is printed with a shortest cycle through it.

Functions are measured from `fn` to their closing brace, outside `#[cfg(test)]` modules,
tests, benches and examples.

    python3 scripts/shape.py                 # every crate: cycles, then functions over 100 lines
    python3 scripts/shape.py --crate gnomon  # one crate (its folder under crates/)
    python3 scripts/shape.py --longest 20    # the 20 longest functions too
    python3 scripts/shape.py --max-cycles 0 --crate gnomon   # exit 1 where there are more
    python3 scripts/shape.py --max-long 1 --crate gnomon     # exit 1 over one long function
    python3 scripts/shape.py --self-test     # the parser on a small crate with known answers
"""

import argparse
import re
import sys
from collections import deque
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LONG = 100

CHAR = re.compile(r"'(?:\\u\{[0-9a-fA-F]+\}|\\.|[^'\\\n])'")
ITEM = re.compile(
    r"^\s*(?:pub(?:\([^)]*\))?\s+)?(?:(?:async|const|unsafe|extern\s+\"C\")\s+)*"
    r"(?:struct|enum|fn|trait|const|static|type|union|mod|macro_rules!)\s+([A-Za-z_][A-Za-z0-9_]*)",
    re.M,
)
USE = re.compile(r"^\s*(pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", re.M)
INLINE = re.compile(r"\b((?:crate|super|self)(?:\s*::\s*[A-Za-z_][A-Za-z0-9_]*)+)")
# A test module's opening, `pub(crate)` and the like included.
TEST_MOD = r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+"
FN = re.compile(r"\bfn\s+([A-Za-z_][A-Za-z0-9_]*)")


def strip(text):
    """The code without comments, string and char literals (same length and lines)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
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
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif re.match(r'(?:b|c)?r#*"', text[i:i + 12]) and (i == 0 or not text[i - 1].isalnum()):
            m = re.match(r'(?:b|c)?r(#*)"', text[i:])
            end = '"' + m.group(1)
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + re.sub(r"[^\n]", " ", text[i + 2:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append('"' + re.sub(r"[^\n]", " ", text[i + 1:j]) + '"')
            i = j + 1
        elif c == "'":
            m = CHAR.match(text, i)
            if m:
                out.append("' '" + " " * (m.end() - i - 3))
                i = m.end()
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def closing(code, open_at):
    """The index of the brace that closes the one at `open_at`."""
    depth = 0
    for j in range(open_at, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


def without_tests(code):
    """The code with its `#[cfg(test)]` items blanked."""
    for m in reversed(list(re.finditer(TEST_MOD + r"\w+\s*\{", code))):
        end = closing(code, m.end() - 1)
        code = code[: m.start()] + re.sub(r"[^\n]", " ", code[m.start(): end + 1]) + code[end + 1:]
    return code


class Crate:
    def __init__(self, folder):
        self.folder = folder
        self.src = folder / "src"
        self.files = {}  # module path (tuple) -> file
        self.code = {}  # file -> stripped code without tests
        test_modules = set()
        for f in sorted(self.src.rglob("*.rs")):
            module = self.module_of(f)
            text = strip(f.read_text())
            for name in re.findall(TEST_MOD + r"(\w+)\s*;", text):
                test_modules.add(module + (name,))
            self.files[module] = f
            self.code[f] = without_tests(text)
        for module in test_modules & set(self.files):
            del self.code[self.files.pop(module)]
        self.items = {f: set(ITEM.findall(c)) for f, c in self.code.items()}
        self.reexports = {f: self.read_reexports(f) for f in self.code}

    def module_of(self, f):
        parts = list(f.relative_to(self.src).with_suffix("").parts)
        if parts[-1] in ("lib", "main", "mod"):
            parts = parts[:-1]
        return tuple(parts)

    def uses(self, f):
        """(is_pub, path segments) of each `use` leaf in `f`."""
        for m in USE.finditer(self.code[f]):
            for path in expand(re.sub(r"\s+", "", m.group(2))):
                yield bool(m.group(1)), path

    def read_reexports(self, f):
        found = {}
        for public, path in self.uses(f):
            if public and path[-1] != "*":
                name = path[-1].split(" as ")[-1]
                found[name] = path
            elif public:
                found.setdefault("*", []).append(path[:-1])
        return found

    def absolute(self, f, path):
        """`path` as a path from the crate root, or None outside the crate."""
        here = list(self.module_of(f))
        if path[0] == "crate":
            return list(path[1:])
        if path[0] == "self":
            return here + list(path[1:])
        if path[0] == "super":
            while path and path[0] == "super":
                here = here[:-1]
                path = path[1:]
            return here + list(path)
        if tuple(here + [path[0]]) in self.files:
            # A path from a submodule declared here (`use focus::X` in lib.rs).
            return here + list(path)
        return None

    def resolve(self, path, seen=()):
        """The file that defines the item at `path` (from the crate root), or None."""
        path = [p.split(" as ")[0] for p in path if p != "self"]
        for k in range(len(path), -1, -1):
            module = tuple(path[:k])
            if module not in self.files:
                continue
            f = self.files[module]
            rest = path[k:]
            if not rest or rest[0] == "*":
                return f
            name = rest[0]
            if name in self.items[f] and (module + (name,)) not in self.files:
                return f
            key = (f, name)
            if key in seen:
                return f
            target = self.reexports[f].get(name)
            if target is not None:
                base = self.absolute(f, target)
                if base is not None:
                    return self.resolve(base[:-1] + [target[-1].split(" as ")[0]], seen + (key,))
            for glob in self.reexports[f].get("*", []):
                base = self.absolute(f, glob + ["x"])
                if base is not None:
                    found = self.resolve(base[:-1] + [name], seen + (key,))
                    if found is not None and name in self.items[found]:
                        return found
            return f
        return None

    def edges(self):
        graph = {f: set() for f in self.code}
        for f, code in self.code.items():
            # A re-export is a facade, not a use: names are followed through it instead.
            paths = [p for public, p in self.uses(f) if not public]
            for m in INLINE.finditer(code):
                paths.append(re.sub(r"\s+", "", m.group(1)).split("::"))
            for path in paths:
                base = self.absolute(f, path)
                if base is None:
                    continue
                target = self.resolve(base)
                if target is not None and target != f:
                    graph[f].add(target)
        return graph


def expand(tree):
    """The leaf paths of a `use` tree: a::{b, c::{d, e}} -> [a,b], [a,c,d], [a,c,e]."""
    if "{" not in tree:
        return [tree.split("::")]
    head, _, rest = tree.partition("{")
    prefix = [p for p in head.split("::") if p]
    inner = rest[: rest.rfind("}")]
    parts, depth, start = [], 0, 0
    for i, c in enumerate(inner):
        depth += c == "{"
        depth -= c == "}"
        if c == "," and depth == 0:
            parts.append(inner[start:i])
            start = i + 1
    parts.append(inner[start:])
    leaves = []
    for part in filter(None, parts):
        for leaf in expand(part):
            leaves.append(prefix + leaf if leaf != ["self"] else prefix)
    return leaves


def components(graph):
    """Strongly connected components (Tarjan, iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                    advanced = True
                    break
                if child in on:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == node:
                        break
                out.append(comp)
    return out


def shortest_cycle(graph, comp):
    """A shortest cycle through the component's first file, inside the component."""
    members, start = set(comp), min(comp)
    previous, queue = {start: None}, deque([start])
    while queue:
        node = queue.popleft()
        for child in sorted(graph[node]):
            if child == start:
                path = [node]
                while previous[path[-1]] is not None:
                    path.append(previous[path[-1]])
                return list(reversed(path)) + [start]
            if child in members and child not in previous:
                previous[child] = node
                queue.append(child)
    return [start]


def functions(crate):
    """(lines, file, line, name) of each function outside tests."""
    found = []
    for f, code in crate.code.items():
        for m in FN.finditer(code):
            brace = code.find("{", m.end())
            semi = code.find(";", m.end())
            if brace < 0 or (0 <= semi < brace):
                continue  # a declaration without a body (trait items)
            end = closing(code, brace)
            first = code.count("\n", 0, m.start()) + 1
            last = code.count("\n", 0, end) + 1
            found.append((last - first + 1, f, first, m.group(1)))
    return found


def self_test():
    """A crate of four files: a circle a -> b -> a through lib.rs's re-export, c outside it
    (its test modules, one `pub(crate)`, import a and b, which does not count), and a 101-line
    function in c."""
    import tempfile

    body = "\n".join(f"    let x{i} = {i};" for i in range(99))
    files = {
        "lib.rs": "mod a;\nmod b;\nmod c;\npub use a::Apple;\n",
        "a.rs": "use crate::b::Bee;\n/// crate::c::nothing in a comment\npub struct Apple(Bee);\n",
        "b.rs": "pub struct Bee;\nfn f() -> crate::Apple { todo!() }\n",
        "c.rs": "fn long() {\n" + body + "\n}\n"
        + "#[cfg(test)]\nmod tests {\n    use crate::a::Apple;\n    const S: &str = \"}\";\n}\n"
        + "#[cfg(test)]\npub(crate) mod scenes {\n    use crate::b::Bee;\n}\n",
    }
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "src"
        src.mkdir()
        for name, text in files.items():
            (src / name).write_text(text)
        crate = Crate(Path(tmp))
        graph = crate.edges()
        circles = [sorted(f.name for f in c) for c in components(graph) if len(c) > 1]
        long = [(n, name) for n, _, _, name in functions(crate) if n > LONG]
    assert circles == [["a.rs", "b.rs"]], circles
    assert graph[src / "c.rs"] == set(), graph
    assert long == [(101, "long")], long
    print("shape.py: self-test passed")


def main():
    if sys.argv[1:] == ["--self-test"]:
        self_test()
        return 0
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--crate", action="append", help="a folder under crates/ (repeatable)")
    parser.add_argument("--longest", type=int, default=0, help="also list the N longest functions")
    parser.add_argument("--max-cycles", type=int, help="exit 1 where a crate has more circles")
    parser.add_argument("--max-long", type=int,
                        help=f"exit 1 where the crates have more functions over {LONG} lines")
    args = parser.parse_args()
    folders = sorted(p for p in (ROOT / "crates").iterdir() if (p / "src").is_dir())
    if args.crate:
        unknown = set(args.crate) - {p.name for p in folders}
        if unknown:
            sys.exit(f"shape.py: no crate folder {', '.join(sorted(unknown))} under crates/")
        folders = [p for p in folders if p.name in args.crate]
    failed, every_function = False, []
    for folder in folders:
        crate = Crate(folder)
        graph = crate.edges()
        circles = [c for c in components(graph) if len(c) > 1]
        print(f"{folder.name}: {len(crate.code)} files, {len(circles)} import circles")
        for comp in sorted(circles, key=len, reverse=True):
            cycle = shortest_cycle(graph, comp)
            names = [str(f.relative_to(crate.src)) for f in cycle]
            print(f"  {len(comp)} files, e.g. {' -> '.join(names)}")
        if args.max_cycles is not None and len(circles) > args.max_cycles:
            failed = True
        every_function += [(n, f, line, name) for n, f, line, name in functions(crate)]
    every_function.sort(key=lambda t: -t[0])
    long = [t for t in every_function if t[0] > LONG]
    print(f"functions over {LONG} lines outside tests: {len(long)}")
    if args.max_long is not None and len(long) > args.max_long:
        failed = True
    for n, f, line, name in every_function[: max(args.longest, len(long))]:
        print(f"  {n:5} {f.relative_to(ROOT)}:{line} {name}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
