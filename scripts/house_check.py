#!/usr/bin/env python3
"""The house's measures: what a new maintainer meets on the first morning.

Prints, for `src/`:
- files over 600 lines (400 for the CLI under `src/bin/`);
- functions over 100 lines (body braces included);
- tuple-grouped parameters (`(a, b): (A, B)` or `x: (A, B)` in a signature);
- import circles between two files (`use crate::…` / `use super::…`,
  re-exports of a `mod.rs` followed to the file that defines the name);
- the names re-exported at the crate root.

Exits 1 when any target of the house issue is missed:
    python3 scripts/house_check.py [--quiet]
"""

import os
import re
import sys

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
SRC = os.path.normpath(SRC)

FILE_LIMIT = 600
CLI_FILE_LIMIT = 400
FUNCTION_LIMIT = 100
TUPLE_PARAMETER_LIMIT = 5
ROOT_NAME_LIMIT = 30


def strip_code(text):
    """The text with comments, string and char literals blanked (newlines kept)."""
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
        elif re.match(r'b?r#*"', text[i:i + 40]) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'b?r(#*)"', text[i:i + 40])
            end = '"' + m.group(1)
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"' or (c == "b" and text.startswith('b"', i) and (i == 0 or not text[i - 1].isalnum())):
            j = i + (2 if c == "b" else 1)
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'":
            m = re.match(r"'(\\.[^']*|[^\\'])'", text[i:i + 12])
            if m:
                out.append(" " * m.end())
                i += m.end()
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


FN_RE = re.compile(r"\bfn\s+([A-Za-z_][A-Za-z0-9_]*)")


def functions(code):
    """(name, first line, lines, signature) of each fn with a body."""
    found = []
    for m in FN_RE.finditer(code):
        # The signature runs to the first `{` or `;` at depth 0 of () and <>.
        j, depth = m.end(), 0
        while j < len(code):
            ch = code[j]
            if ch in "([":
                depth += 1
            elif ch in ")]":
                depth -= 1
            elif depth == 0 and ch in "{;":
                break
            j += 1
        if j >= len(code) or code[j] == ";":
            continue
        signature = code[m.start():j]
        k, depth = j, 0
        while k < len(code):
            if code[k] == "{":
                depth += 1
            elif code[k] == "}":
                depth -= 1
                if depth == 0:
                    break
            k += 1
        first = code.count("\n", 0, m.start()) + 1
        last = code.count("\n", 0, k) + 1
        found.append((m.group(1), first, last - first + 1, signature))
    return found


def split_top(s, sep=","):
    parts, depth, cur = [], 0, []
    for ch in s:
        if ch in "(<[":
            depth += 1
        elif ch in ")>]":
            depth -= 1
        if ch == sep and depth == 0:
            parts.append("".join(cur))
            cur = []
        else:
            cur.append(ch)
    if "".join(cur).strip():
        parts.append("".join(cur))
    return parts


def tuple_parameters(signature):
    """Parameters of a signature grouped as tuples."""
    open_ = signature.find("(")
    if open_ < 0:
        return []
    depth, j = 0, open_
    while j < len(signature):
        if signature[j] == "(":
            depth += 1
        elif signature[j] == ")":
            depth -= 1
            if depth == 0:
                break
        j += 1
    grouped = []
    for p in split_top(signature[open_ + 1:j]):
        p = p.strip().replace("->", "=>")
        if not p:
            continue
        pattern, _, ty = p.partition(":")
        pattern, ty = pattern.strip(), ty.strip().lstrip("&").strip()
        ty = re.sub(r"^(mut\s+|'\w+\s+)", "", ty)
        if ty.startswith("(dyn") or ty.startswith("dyn"):
            continue
        if pattern.startswith("(") or (ty.startswith("(") and ty != "()"):
            grouped.append(p)
    return grouped


def module_of(path):
    rel = os.path.relpath(path, SRC)[:-3].split(os.sep)
    if rel[-1] == "mod":
        rel = rel[:-1]
    if rel == ["lib"]:
        rel = []
    return tuple(rel)


def main():
    quiet = "--quiet" in sys.argv
    files = {}
    for root, _, names in os.walk(SRC):
        for name in names:
            if name.endswith(".rs"):
                path = os.path.join(root, name)
                with open(path, encoding="utf-8") as f:
                    files[path] = f.read()
    lib_modules = {module_of(p): p for p in files if not os.path.relpath(p, SRC).startswith("bin")}
    problems = 0

    def report(title, rows, limit_ok):
        nonlocal problems
        if not limit_ok:
            problems += 1
        if rows and (not quiet or not limit_ok):
            print(f"{title}:")
            for row in rows:
                print(f"  {row}")

    # File sizes.
    big = []
    for path, text in sorted(files.items()):
        lines = text.count("\n")
        rel = os.path.relpath(path, SRC)
        limit = CLI_FILE_LIMIT if rel.startswith("bin") else FILE_LIMIT
        if lines > limit:
            big.append(f"{rel}: {lines} lines (limit {limit})")
    report(f"files over their limit ({len(big)})", big, not big)

    # Function sizes and tuple parameters.
    long_fns, tuples = [], []
    codes = {}
    for path, text in sorted(files.items()):
        code = strip_code(text)
        codes[path] = code
        rel = os.path.relpath(path, SRC)
        for name, first, length, signature in functions(code):
            if length > FUNCTION_LIMIT:
                long_fns.append((length, f"{rel}:{first} {name}: {length} lines"))
            for p in tuple_parameters(signature):
                tuples.append(f"{rel}:{first} {name}: {' '.join(p.split())}")
    long_fns.sort(reverse=True)
    report(f"functions over {FUNCTION_LIMIT} lines ({len(long_fns)})", [r for _, r in long_fns], not long_fns)
    report(
        f"tuple-grouped parameters ({len(tuples)}, limit {TUPLE_PARAMETER_LIMIT})",
        tuples,
        len(tuples) <= TUPLE_PARAMETER_LIMIT,
    )

    # Import circles between two files.
    reexports = {}  # (module, name) -> module it comes from
    for path, code in codes.items():
        mod = module_of(path)
        for m in re.finditer(r"pub(?:\([^)]*\))?\s+use\s+([^;]+);", code):
            for target in expand_use(m.group(1), mod):
                reexports[(mod, target[-1])] = tuple(target[:-1])
    edges = {}
    for path, code in codes.items():
        if os.path.relpath(path, SRC).startswith("bin"):
            continue
        mod = module_of(path)
        targets = set()
        for m in re.finditer(r"\buse\s+([^;]+);", code):
            for target in expand_use(m.group(1), mod):
                targets.add(resolve(target, lib_modules, reexports))
        for m in re.finditer(r"\b(crate|super)(::[A-Za-z_][A-Za-z0-9_]*)+", code):
            target = expand_use(m.group(0), mod)
            for t in target:
                targets.add(resolve(t, lib_modules, reexports))
        targets.discard(None)
        targets.discard(mod)
        edges[mod] = targets
    circles = []
    for a, targets in edges.items():
        for b in targets:
            if a < b and a in edges.get(b, ()) and not is_ancestor(a, b) and not is_ancestor(b, a):
                circles.append(f"{'/'.join(a)} <-> {'/'.join(b)}")
    report(f"import circles between two files ({len(circles)})", sorted(circles), not circles)

    # Names at the crate root.
    lib = codes[os.path.join(SRC, "lib.rs")]
    root_names = []
    for m in re.finditer(r"^pub\s+use\s+([^;]+);", lib, re.M):
        root_names += [t[-1] for t in expand_use(m.group(1), ())]
    report(
        f"names re-exported at the crate root ({len(root_names)}, limit {ROOT_NAME_LIMIT})",
        [", ".join(root_names)] if not quiet else [],
        len(root_names) <= ROOT_NAME_LIMIT,
    )
    print("house: all targets met" if problems == 0 else f"house: {problems} target(s) missed")
    return 1 if problems else 0


def is_ancestor(a, b):
    return len(a) < len(b) and b[: len(a)] == a


def expand_use(tree, mod):
    """The absolute paths (tuples of segments) a `use` tree names."""
    tree = " ".join(tree.split())
    out = []

    def walk(prefix, t):
        t = t.strip()
        if not t:
            return
        brace = t.find("{")
        if brace >= 0 and t.endswith("}"):
            head = [s for s in t[:brace].strip().rstrip(":").split("::") if s]
            for part in split_top(t[brace + 1:-1]):
                walk(prefix + head, part)
            return
        t = t.split(" as ")[0].strip()
        segs = [s for s in t.split("::") if s]
        if segs == ["self"]:
            segs = []
        elif segs and segs[-1] == "self":
            segs = segs[:-1]
        out.append(prefix + segs)

    walk([], tree)
    result = []
    for segs in out:
        if not segs:
            continue
        if segs[0] == "crate":
            result.append(tuple(segs[1:]))
        elif segs[0] in ("super", "self"):
            base = list(mod)
            while segs and segs[0] in ("super", "self"):
                if segs[0] == "super":
                    base = base[:-1]
                segs = segs[1:]
            result.append(tuple(base + segs))
        elif segs[0] in ("std", "core", "alloc"):
            continue
        else:
            # A path from a child module declared in this file.
            result.append(tuple(list(mod) + segs))
    return [r for r in result if r]


def resolve(path, modules, reexports, depth=0):
    """The module file that defines the item `path` names."""
    for k in range(len(path), -1, -1):
        mod = tuple(path[:k])
        if mod in modules:
            if k < len(path) and (mod, path[k]) in reexports and depth < 8:
                origin = reexports[(mod, path[k])]
                if origin != mod:
                    return resolve(origin + (path[k],), modules, reexports, depth + 1)
            return mod
    return None


if __name__ == "__main__":
    sys.exit(main())
