#!/usr/bin/env python3
"""Writes generated mutants of the product's sources, a fixed-seed sample per component, in the format
tests/mutation/run.sh reads (see its header), each block with a `component =` line.

Operators (one change on one line each; strings, character literals and comments are never mutated):
  ror      relational operator replacement: <  <=  >  >=  ==  != (each to its neighbour or negation)
  aor      arithmetic operator replacement: + <-> -, * <-> /, and the compound forms += -= *= /=
  lcr      logical connector replacement: && <-> ||
  neg      an if/while condition negated: if (c) -> if (!(c))
  bool     a boolean literal flipped: true <-> false
  obo      off by one on a bound or an index: an integer literal k in a comparison or a subscript -> k + 1
  crp      constant replacement: a floating literal x -> 2 * x (0.0 -> 1.0)
  sdl      statement deletion: a one-line call, assignment or increment replaced by ';'
  swap     swapped arguments or fields: f(a, b) -> f(b, a) and {a, b} -> {b, a}

The sample: every candidate of a component is listed in a fixed order, the equivalent mutants of
tests/mutation/equivalent.toml are taken out (each has a reason there), and N are drawn taking the
operators in turn (so that each is tried), each operator's candidates ranked by a hash of the seed,
the component and the candidate's file and text. The same seed and sources give the same sample; an
edit elsewhere leaves it as it was unless a new candidate ranks into it; a sample of N is the head of
a sample of N + k with the same seed.

Usage: generate.py [--per-component N] [--seed S] [--component NAME]... [--all] [--list-components]
Source: the operator set of Offutt et al., "An Experimental Determination of Sufficient Mutant
Operators" (ACM TOSEM 1996), and of Petrovic & Ivankovic, "State of Mutation Testing at Google"
(ICSE-SEIP 2018), as listed in docs/testing.md ("Generated mutants").
"""
import argparse
import hashlib
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent

# Lines never mutated: preprocessor, logging (its text is not behaviour a test pins), static checks,
# and lines that only declare.
SKIP_LINE = re.compile(r"^\s*(#|static_assert|DT_LOG|using |namespace |template\b|friend |case |default:)")
SKIP_ANYWHERE = re.compile(r"\bDT_LOG(_ONCE|_CATEGORY)?\b|\bassert\(|\boperator\b")


def mask_code(lines):
    """Yields (lineno, text, masked): masked has string/char literals and comments blanked."""
    in_block = False
    for lineno, text in enumerate(lines, 1):
        out = []
        i, n = 0, len(text)
        raw = False
        while i < n:
            c = text[i]
            if in_block:
                if text.startswith("*/", i):
                    in_block = False
                    out.append("  ")
                    i += 2
                else:
                    out.append(" ")
                    i += 1
            elif text.startswith("/*", i):
                in_block = True
                out.append("  ")
                i += 2
            elif text.startswith("//", i):
                out.append(" " * (n - i))
                break
            elif c in "\"'":
                if c == '"' and i > 0 and text[i - 1] == "R":
                    raw = True  # raw strings: leave the line alone
                j = i + 1
                while j < n and text[j] != c:
                    j += 2 if text[j] == "\\" else 1
                out.append(c + " " * (min(j, n) - i - 1) + (c if j < n else ""))
                i = j + 1
            else:
                out.append(c)
                i += 1
        yield lineno, text, ("" if raw else "".join(out)[:n])


RELATIONAL = {"<": ["<="], "<=": ["<"], ">": [">="], ">=": [">"], "==": ["!="], "!=": ["=="]}
ARITHMETIC = {"+": "-", "-": "+", "*": "/", "/": "*", "+=": "-=", "-=": "+=", "*=": "/=", "/=": "*="}
OP_RE = re.compile(r"(?<=\s)(<=|>=|==|!=|<|>|\+=|-=|\*=|/=|\+|-|\*|/|&&|\|\|)(?=\s)")
INT_IN_BOUND = re.compile(r"(?<=[\s\[(])(\d+)(?=[\s\])])")
FLOAT_RE = re.compile(r"(?<![\w.])(\d+\.\d*(?:e[-+]?\d+)?|\d+e[-+]?\d+)(f?)(?![\w.])")
BOOL_RE = re.compile(r"\b(true|false)\b")
COND_RE = re.compile(r"^(\s*(?:\}\s*else\s+)?(?:if|while)\s*)\((.*)\)(\s*\{?)\s*$")
CALL2_RE = re.compile(r"(\w+)\(([A-Za-z_][\w.]*(?:->[\w.]+)*), ([A-Za-z_][\w.]*(?:->[\w.]+)*)\)")
BRACE2_RE = re.compile(r"\{([A-Za-z_][\w.]*), ([A-Za-z_][\w.]*)\}")
STMT_ASSIGN = re.compile(r"^\s*[A-Za-z_][\w.\[\]]*(?:->[\w.\[\]]+)*\s*(=|\+=|-=|\*=|/=|\|=|&=)\s.*;\s*$")
STMT_CALL = re.compile(r"^\s*[A-Za-z_][\w:.]*(?:->[\w.]+)*(?:\(.*\))+;\s*$")
STMT_INCR = re.compile(r"^\s*(\+\+|--)?[A-Za-z_][\w.\[\]]*(\+\+|--)?;\s*$")


# The size in an array declaration (`char buf[32];`, `std::array<T, 4> a{}` is not matched): one more
# element changes no behaviour of code that uses sizeof or the declared size.
ARRAY_DECL = re.compile(r"^\s*(?:static\s+)?(?:const\s+)?[A-Za-z_][\w:<>]*\s+\w+\s*\[\s*\w+\s*\]$")

# Calls whose two arguments commute (a swap is an equivalent mutant) or that are not calls.
NOT_SWAPPED = {"if", "while", "for", "switch", "return", "max", "min", "fmax", "fmin", "hypot", "swap",
               "equal", "add", "plus", "multiplies", "dot"}


def balanced(s):
    depth = 0
    for c in s:
        depth += (c in "([{") - (c in ")]}")
        if depth < 0:
            return False
    return depth == 0


def candidates_of_line(text, masked):
    """Yields (operator, mutated line) for one source line."""
    if not masked.strip() or SKIP_LINE.match(masked) or SKIP_ANYWHERE.search(masked):
        return

    def at(start, end, new):
        return text[:start] + new + text[end:]

    for m in OP_RE.finditer(masked):
        op = m.group(1)
        if op in RELATIONAL:
            for new in RELATIONAL[op]:
                yield "ror", at(m.start(), m.end(), new)
        elif op in ("&&", "||"):
            yield "lcr", at(m.start(), m.end(), "||" if op == "&&" else "&&")
        elif op in ARITHMETIC:
            yield "aor", at(m.start(), m.end(), ARITHMETIC[op])
    if re.search(r"\s(<|<=|>|>=|==|!=)\s|\[", masked):
        for m in INT_IN_BOUND.finditer(masked):
            if ARRAY_DECL.search(masked[:m.end() + 1]):
                continue   # an array one element larger (char buf[161]) is an equivalent mutant
            yield "obo", at(m.start(), m.end(), f"({m.group(1)} + 1)")
    for m in FLOAT_RE.finditer(masked):
        value, suffix = m.group(1), m.group(2)
        new = ("1.0" + suffix) if float(value) == 0.0 else f"(2 * {value}{suffix})"
        yield "crp", at(m.start(), m.end(), new)
    for m in BOOL_RE.finditer(masked):
        yield "bool", at(m.start(), m.end(), "false" if m.group(1) == "true" else "true")
    cond = COND_RE.match(masked)
    if cond and balanced(cond.group(2)):
        start, end = cond.start(2), cond.end(2)
        yield "neg", at(start, end, "!(" + text[start:end] + ")")
    for m in CALL2_RE.finditer(masked):
        if m.group(2) != m.group(3) and m.group(1) not in NOT_SWAPPED:
            yield "swap", at(m.start(2), m.end(3), m.group(3) + ", " + m.group(2))
    for m in BRACE2_RE.finditer(masked):
        if m.group(1) != m.group(2):
            yield "swap", at(m.start(1), m.end(2), m.group(2) + ", " + m.group(1))
    stripped = masked.strip()
    if (STMT_ASSIGN.match(masked) or STMT_CALL.match(masked) or STMT_INCR.match(masked)) \
            and balanced(stripped) and not stripped.startswith(("return", "break", "continue", "throw")):
        indent = text[: len(text) - len(text.lstrip())]
        yield "sdl", indent + ";"


def sources_of(component, headers=True):
    files = []
    for pattern in component["sources"]:
        for path in sorted((ROOT).glob(pattern)):
            rel = path.relative_to(ROOT).as_posix()
            if path.suffix in ((".cpp", ".h") if headers else (".cpp",)) and not any(
                    re.search(x, rel) for x in component.get("exclude", [])):
                files.append(rel)
    return files


def candidates_of(component, equivalent, headers):
    """All candidates of one component in a fixed order, less the equivalent ones."""
    out, dropped = [], 0
    for rel in sources_of(component, headers):
        whole = (ROOT / rel).read_text(encoding="utf-8")
        lines = whole.split("\n")
        for lineno, text, masked in mask_code(lines):
            # run.sh finds a mutant by its text, leading spaces stripped, which must occur exactly
            # once in the file (a line unique as a whole can still be inside a longer one)
            if not masked or whole.count(text.strip()) != 1:
                continue
            for op, mutated in candidates_of_line(text, masked):
                if mutated == text:
                    continue
                if (rel, text.strip(), mutated.strip()) in equivalent:
                    dropped += 1
                    continue
                out.append((rel, lineno, op, text, mutated))
    return out, dropped


def sample(cands, n, seed, name):
    """N candidates, the operators taken in turn (their order drawn from the seed), each operator's
    candidates ranked by a hash of the seed and the candidate's file and text (not its line number).
    So an edit elsewhere in a component (lines moved, a file added) leaves the sample as it was unless
    a new candidate ranks into it, and a smaller sample is the head of a larger one of the same seed."""
    def key(*parts):
        return hashlib.sha1("\n".join((str(seed), name) + parts).encode()).hexdigest()
    by_op = {}
    for c in cands:
        by_op.setdefault(c[2], []).append(c)
    for group in by_op.values():
        group.sort(key=lambda c: key(c[0], c[3].strip(), c[4].strip()), reverse=True)
    chosen, ops = [], sorted(by_op, key=lambda op: key(op))
    while len(chosen) < n and any(by_op.values()):
        for op in ops:
            if by_op[op] and len(chosen) < n:
                chosen.append(by_op[op].pop())
    return chosen


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--per-component", type=int, default=8, metavar="N")
    parser.add_argument("--seed", default="1")
    parser.add_argument("--component", action="append", default=[], metavar="NAME")
    parser.add_argument("--all", action="store_true", help="every candidate, no sample (a night's run)")
    parser.add_argument("--headers", action="store_true",
                        help="draw from headers too (each header mutant recompiles its includers twice)")
    parser.add_argument("--list-components", action="store_true")
    args = parser.parse_args()

    config = tomllib.loads((HERE / "components.toml").read_text(encoding="utf-8"))["component"]
    equivalent = {(e["file"], e["find"].strip(), e["replace"].strip())
                  for e in tomllib.loads((HERE / "equivalent.toml").read_text(encoding="utf-8"))
                  .get("equivalent", [])}
    unknown = [c for c in args.component if c not in config]
    if unknown:
        print(f"generate.py: no component named {', '.join(unknown)} "
              f"(known: {', '.join(config)})", file=sys.stderr)
        return 2
    if args.per_component < 1:
        print("generate.py: --per-component must be at least 1", file=sys.stderr)
        return 2
    samples = []
    for name, component in config.items():
        if args.component and name not in args.component:
            continue
        cands, dropped = candidates_of(component, equivalent, args.headers)
        if args.list_components:
            print(f"{name:12} {len(sources_of(component, args.headers)):4} files {len(cands):6} "
                  f"candidates {dropped:3} equivalent")
            continue
        chosen = cands if args.all else sample(cands, args.per_component, args.seed, name)
        print(f"# component {name}: {len(chosen)} of {len(cands)} candidates "
              f"({dropped} marked equivalent), seed {args.seed}")
        samples.append((name, component, chosen))
    # Interleaved (the first of each component, then the second, ...): a run stopped early has
    # tried every component as far as it went.
    for k in range(max((len(c) for _, _, c in samples), default=0)):
        for name, component, chosen in samples:
            if k >= len(chosen):
                continue
            rel, lineno, op, text, mutated = chosen[k]
            tag = hashlib.sha1(f"{rel}\n{text}\n{mutated}".encode()).hexdigest()[:8]
            print(f"\n[gen-{name}-{Path(rel).stem}-{lineno}-{op}-{tag}]")
            print(f"file = {rel}")
            print(f"find = {text}")
            print(f"replace = {mutated}")
            print(f"tests = {' '.join(component['tests'])}")
            print(f"build = {' '.join(component['build'])}")
            print(f"component = {name}")
            print(f"breaks = {op} at {rel}:{lineno}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
