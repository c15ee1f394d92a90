"""A GLSL preprocessor for reading a pasted shader as a compiler would (no GL): comments
removed, line continuations joined, ``#if``/``#ifdef``/``#ifndef``/``#elif``/``#else``/
``#endif`` decided with a given set of defines (Shadertoy's, say), and the active text's
macros expanded (object-like and function-like, a macro never expanding inside itself).

facet.lab.dialect reads the result to decide what a file is (which entry point it defines
in the branches that compile); the driver still compiles the original text, so its
messages keep the user's lines.
"""

from __future__ import annotations

import ast
import operator
import re
from dataclasses import dataclass

_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
_DIRECTIVE = re.compile(r"^\s*#\s*(\w+)\s*(.*)$")
_DEFINE = re.compile(r"(\w+)(\([^)]*\))?\s*(.*)$", re.S)
_TOKEN = re.compile(r"[A-Za-z_]\w*|\d[\w.]*|\S")
MAX_EXPANSIONS = 10_000  # a macro expanding without end stops here (the compiler decides)


@dataclass(frozen=True)
class Macro:
    params: tuple[str, ...] | None  # None: object-like
    body: str


@dataclass(frozen=True)
class Preprocessed:
    """``text``: the active code, macros expanded, one line per source line (directive
    lines empty); ``macros``: those defined at the end."""

    text: str
    macros: dict


def preprocess(text: str, defines: dict | None = None) -> Preprocessed:
    """``text`` as the preprocessor passes it on with ``defines`` ({name: value}) set."""
    text = _COMMENT.sub(lambda m: "\n" * m.group().count("\n") or " ", text)
    lines = _join_continued(text.split("\n"))
    macros = {name: Macro(None, str(value)) for name, value in (defines or {}).items()}
    stack: list[list[bool]] = []  # per open #if: [this branch active, some branch taken]
    out = []
    for line in lines:
        m = _DIRECTIVE.match(line)
        active = all(frame[0] for frame in stack)
        if m is None:
            out.append(_expand(line, macros) if active else "")
            continue
        out.append("")
        word, rest = m.group(1), m.group(2).strip()
        if word in ("if", "ifdef", "ifndef"):
            value = active and _condition(word, rest, macros)
            stack.append([value, value or not active])
        elif word == "elif" and stack:
            frame = stack[-1]
            outer = all(f[0] for f in stack[:-1])
            frame[0] = not frame[1] and outer and _condition("if", rest, macros)
            frame[1] = frame[1] or frame[0]
        elif word == "else" and stack:
            frame = stack[-1]
            frame[0] = not frame[1] and all(f[0] for f in stack[:-1])
            frame[1] = True
        elif word == "endif" and stack:
            stack.pop()
        elif active and word == "define":
            d = _DEFINE.match(rest)
            if d:
                params = None if d.group(2) is None else tuple(
                    p.strip() for p in d.group(2)[1:-1].split(",") if p.strip())
                macros[d.group(1)] = Macro(params, d.group(3).strip())
        elif active and word == "undef":
            macros.pop(rest.split()[0] if rest else "", None)
    return Preprocessed("\n".join(out), macros)


def _join_continued(lines: list[str]) -> list[str]:
    """Backslash-continued lines joined into the first; the others left empty (the count
    of lines stays)."""
    out, pending, extra = [], "", 0
    for line in lines:
        if line.endswith("\\"):
            pending += line[:-1] + " "
            extra += 1
            continue
        out.append(pending + line)
        out.extend([""] * extra)
        pending, extra = "", 0
    if pending:
        out.append(pending)
    return out


def _condition(word: str, rest: str, macros: dict) -> bool:
    if word in ("ifdef", "ifndef"):
        name = rest.split()[0] if rest.split() else ""
        return (name in macros) == (word == "ifdef")
    expr = re.sub(r"\bdefined\s*\(\s*(\w+)\s*\)|\bdefined\s+(\w+)",
                  lambda m: "1" if (m.group(1) or m.group(2)) in macros else "0", rest)
    expr = _expand(expr, macros)
    expr = re.sub(r"[A-Za-z_]\w*", "0", expr)  # what is still a name counts as 0
    return bool(_evaluate(expr))


_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
        ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.LShift: operator.lshift,
        ast.RShift: operator.rshift, ast.BitAnd: operator.and_, ast.BitOr: operator.or_,
        ast.BitXor: operator.xor, ast.Eq: operator.eq, ast.NotEq: operator.ne,
        ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge}


def _evaluate(expr: str) -> int:
    """A preprocessor expression's integer value (C operators); 0 when it is not one."""
    text = re.sub(r"(\d+)[uU]\b", r"\1", expr)
    text = text.replace("&&", " and ").replace("||", " or ").replace("/", "//")
    text = re.sub(r"!(?!=)", " not ", text)
    try:
        return int(_value(ast.parse(text.strip() or "0", mode="eval").body))
    except (SyntaxError, ValueError, TypeError, ZeroDivisionError, RecursionError):
        return 0


def _value(node):
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return node.value
    if isinstance(node, ast.BoolOp):
        values = [_value(v) for v in node.values]
        return int(all(values) if isinstance(node.op, ast.And) else any(values))
    if isinstance(node, ast.UnaryOp):
        v = _value(node.operand)
        return {ast.Not: lambda: int(not v), ast.USub: lambda: -v, ast.UAdd: lambda: v,
                ast.Invert: lambda: ~int(v)}[type(node.op)]()
    if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
        return _OPS[type(node.op)](_value(node.left), _value(node.right))
    if isinstance(node, ast.Compare) and len(node.ops) == 1 and type(node.ops[0]) in _OPS:
        return int(_OPS[type(node.ops[0])](_value(node.left), _value(node.comparators[0])))
    if isinstance(node, ast.IfExp):
        return _value(node.body) if _value(node.test) else _value(node.orelse)
    raise ValueError("not a preprocessor expression")


def _expand(text: str, macros: dict, hidden: frozenset = frozenset(), budget=None) -> str:
    """``text`` with its macros expanded (a macro's own name stays as it is inside it)."""
    budget = budget if budget is not None else [MAX_EXPANSIONS]
    out, pos = [], 0
    for m in re.finditer(r"[A-Za-z_]\w*", text):
        name = m.group()
        macro = macros.get(name)
        if m.start() < pos or macro is None or name in hidden or budget[0] <= 0:
            continue
        end = m.end()
        if macro.params is None:
            body = macro.body
        else:
            args, end = _arguments(text, m.end())
            if args is None:
                continue  # a function-like macro's name without a call stays a name
            if len(args) == 1 and not args[0].strip() and not macro.params:
                args = []
            body = _substitute(macro, [_expand(a, macros, hidden, budget) for a in args])
        budget[0] -= 1
        out.append(text[pos:m.start()])
        out.append(_expand(body, macros, hidden | {name}, budget))
        pos = end
    out.append(text[pos:])
    return "".join(out)


def _arguments(text: str, start: int):
    """The arguments of a call whose name ends at ``start`` ((args, end) or (None, start))."""
    i = start
    while i < len(text) and text[i].isspace():
        i += 1
    if i >= len(text) or text[i] != "(":
        return None, start
    depth, args, begin = 0, [], i + 1
    for j in range(i, len(text)):
        c = text[j]
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
            if depth == 0:
                args.append(text[begin:j])
                return args, j + 1
        elif c == "," and depth == 1:
            args.append(text[begin:j])
            begin = j + 1
    return None, start


def _substitute(macro: Macro, args: list[str]) -> str:
    values = dict(zip(macro.params, args, strict=False))
    return re.sub(r"[A-Za-z_]\w*", lambda m: values.get(m.group(), m.group()), macro.body)
