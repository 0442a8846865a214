#!/usr/bin/env python3
"""Checks that no C++ function is longer than the project allows (docs/developing.md): 80 lines in
src/ and app/, 120 in the Python bindings (python/src/), where one function may register a class.

    scripts/check-function-length.py [ROOT]     check the tree at ROOT (default: this repository)
    scripts/check-function-length.py --list N   print every function longer than N lines, longest first
    scripts/check-function-length.py --self-test   check that a planted long function is caught

A function is a brace block at namespace or class scope whose opening brace follows a parameter list
(with its qualifiers, a trailing return type or a constructor's initialiser list); its length is
the lines from its first line (the one holding its name) to its closing brace. Lambdas and local
classes count towards the function that holds them; a table initialised at namespace scope is not
a function. Exit status 0 when every function is within its limit; 1 with one line per violation.
"""
import pathlib
import re
import sys
import tempfile

LIMITS = (("src", 80), ("app", 80), ("python/src", 120))
SCOPE = re.compile(r'^(?:template\s*<[^{]*>\s*)?(?:namespace|class|struct|union|enum|extern\s+"C")\b')
AFTER_PARAMETERS = re.compile(
    r'\)\s*(?:const|noexcept(?:\s*\([^)]*\))?|override|final|mutable|&|&&|\s)*(?:->[^{;]*)?$')
INITIALISERS = re.compile(r'\)\s*(?:noexcept\s*)?:\s*[A-Za-z_]')


def blanked(text: str) -> str:
    """The source with comments, string and character literals replaced by spaces (newlines kept),
    so that braces inside them do not count."""
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
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            delimiter = text[i + 2:text.find("(", i + 2)]
            j = text.find(")" + delimiter + '"', i)
            j = n if j < 0 else j + len(delimiter) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (j + 1 - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    # Preprocessor lines (includes, macros) end no statement: blank them too.
    return re.sub(r"(?m)^[ \t]*#.*$", lambda m: " " * len(m.group(0)), "".join(out))


def functions(text: str):
    """(name, first line, last line) of every function defined at namespace or class scope."""
    code = blanked(text)
    found = []
    stack = []  # "scope", "function" or "other" per open brace
    statement_start = 0  # where the text before the next brace begins
    function_start = None  # (offset of its first line, open brace offset) of the function being read
    for at, c in enumerate(code):
        if c in ";}" and (not stack or stack[-1] == "scope"):
            statement_start = at + 1
        if c == "{":
            inside_function = any(kind != "scope" for kind in stack)
            head = code[statement_start:at].strip()
            if inside_function:
                kind = "other"
            elif SCOPE.match(head):
                kind = "scope"
            elif AFTER_PARAMETERS.search(head) or INITIALISERS.search(head):
                kind = "function"
                first = statement_start + (len(code[statement_start:at]) - len(code[statement_start:at].lstrip()))
                function_start = (first, head)
            else:
                kind = "other"
            stack.append(kind)
            if kind == "scope":
                statement_start = at + 1
        elif c == "}" and stack:
            kind = stack.pop()
            if kind == "function" and function_start is not None:
                first, head = function_start
                name = re.findall(r"([A-Za-z_][\w:~]*(?:operator\S*)?)\s*\(", head)
                found.append((name[0] if name else head[:40], code.count("\n", 0, first) + 1,
                              code.count("\n", 0, at) + 1))
                function_start = None
            if not stack or stack[-1] == "scope":
                statement_start = at + 1
    return found


def long_functions(root: pathlib.Path, threshold=None):
    """(lines, limit, 'path:line: name') for every function over its folder's limit (or `threshold`)."""
    found = []
    for folder, limit in LIMITS:
        limit = threshold if threshold is not None else limit
        base = root / folder
        if not base.is_dir():
            continue
        for path in sorted(base.rglob("*.[ch]pp")):
            for name, first, last in functions(path.read_text(encoding="utf-8")):
                lines = last - first + 1
                if lines > limit:
                    found.append((lines, limit, f"{path.relative_to(root)}:{first}: {name}"))
    return found


def self_test() -> int:
    """A 90-line function in src/ must be caught; an 80-line one, a long namespace-scope table, a
    long class and a function with a long lambda of its own under the limit must not."""
    body = "".join(f"  x += {i};\n" for i in range(86))
    table = "".join(f"    {{\"k{i}\", {i}}},\n" for i in range(100))
    short = "".join(f"  x += {i};\n" for i in range(76))
    text = (f"namespace a {{\nint long_one(int x) {{\n  // a }} in a comment\n{body}  return x;\n}}\n"
            f"const Table t = {{\n{table}}};\n"
            f"struct S {{\n  int f(int x) const {{\n{short}    return x;\n  }}\n"
            f"  int g(int x) {{ return x; }}\n{''.join(f'  int m{i} = 0;' + chr(10) for i in range(90))}}};\n"
            f"int ok(int x) {{\n{short}  return x;\n}}\n}}  // namespace a\n")
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / "src").mkdir()
        (root / "src" / "a.cpp").write_text(text)
        found = long_functions(root)
    ok = len(found) == 1 and "long_one" in found[0][2] and found[0][0] == 90
    print("check-function-length self-test: " + ("passed" if ok else f"FAILED {found}"))
    return 0 if ok else 1


def main() -> int:
    args = sys.argv[1:]
    if args == ["--self-test"]:
        return self_test()
    threshold = None
    if args[:1] == ["--list"]:
        threshold = int(args[1])
        args = args[2:]
    root = pathlib.Path(args[0]) if args else pathlib.Path(__file__).resolve().parent.parent
    found = sorted(long_functions(root, threshold), reverse=True)
    for lines, limit, where in found:
        print(f"check-function-length: {where}: {lines} lines (limit {limit})")
    if threshold is not None:
        return 0
    if not found:
        print("check-function-length: every function in src/, app/ and python/src/ is within its limit")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
