#!/usr/bin/env python3
"""Structure checks of the source tree (issue 19): layers, file length, function length.

Usage: tools/scripts/check_structure.py [--root DIR]
Exit status 0 when every rule holds (allow-listed offenders aside), 1 otherwise. Python 3
standard library only. Run by the CMake target `check_structure` and the CTest test
`Structure.check_structure` (so CI, tools/scripts/run_tests.sh, enforces it); its own unit
test is tools/scripts/check_structure_test.py (`Structure.check_structure_selftest`).

Rules
1. No import runs up a layer. Every folder of common/, services/ and tools/ has a layer (LAYERS
   below, the one place they are defined); a CMake target has the layer of the folder whose
   CMakeLists.txt defines it. An `#include "folder/file.h"` of a non-test source, or a
   `target_link_libraries` of a non-test target, naming a folder or target of a HIGHER layer
   is an offence. Same-layer imports are allowed (CMake refuses cycles between targets).
   Tests (below) sit above everything and are not checked.
2. No non-test .cpp/.h over MAX_FILE_LINES lines (physical lines).
3. No function over MAX_FUNCTION_LINES lines outside tests. A function's length is counted in
   physical lines from the first line of its declaration (template line and return type
   included) to its closing brace, blank and comment lines included. Bodies are found by
   brace matching over the source with comments, string, character and raw-string literals
   and preprocessor lines blanked out; a brace opens a function body when it sits at namespace
   or class scope and follows a parameter list (`) const noexcept override -> T {`, a
   constructor's member-initializer list, or a lambda bound at namespace scope). Lambdas and
   local classes inside a function count towards their enclosing function.

Tests: files under tests/, files named *_test.cpp / *_test.h / *_test_util.* / *_fixture.h,
and the test-only helpers listed in TEST_ONLY_FILES.

The ALLOWED_* lists name today's offenders that other work (issue 19) is removing: each entry
says why. An allow-listed offender that no longer offends is reported as stale (and fails the
check), so the lists only shrink: removing an entry is how its fix is proven.
"""

import argparse
import os
import re
import sys

MAX_FILE_LINES = 400
MAX_FUNCTION_LINES = 60

# Layers, lowest first. A folder may import (include, link) its own layer and the ones below.
LAYERS = [
    ("foundation", ["common/base", "common/geometry", "common/localization", "common/timing",
                    "common/cli", "common/sqlite"]),
    # Pure building blocks and vocabulary: image kernels, the tile layout and store, camera
    # calibration, the supervisor's pure fleet logic.
    ("primitives", ["common/imaging", "common/mosaic", "common/calibration", "common/fleet"]),
    ("tracking", ["common/tracking"]),
    # Algorithms over the tracker: mosaic building and re-mapping, map matching, the simulator
    # (its corridor scenes use mapmatch's landmarks).
    ("algorithms", ["common/mapping", "common/mapmatch", "common/sim"]),
    # Global relocalization: over the tracker (verification) and mapmatch (mean shift).
    ("relocalization", ["common/relocalization"]),
    # Adapters: process plumbing (logging, signals, sd_notify, child processes), generic files
    # (io), the project's own files (run_io: over tracking and mapmatch), the rectifier
    # camera.json asks for (replay's and the agent's), DDS, cameras, metrics, offline replay, the
    # stored mosaic's upkeep jobs (re-mapping, vehicle standing, the place-index cache: over
    # mapping and relocalization), the fleet on DDS.
    ("adapters", ["common/runtime", "common/io", "common/run_io", "common/rectification",
                  "common/transport", "common/camera_io", "common/metrics", "common/replay",
                  "common/mosaic_upkeep", "common/fleet_link"]),
    ("services", ["services/map_server", "services/tracker_agent",
                  "services/fleet_supervisor"]),
    ("tools", ["tools/peers", "tools/live_sim", "tools/fleetctl", "tools/bench", "tools/fuzz"]),
]

# Upward imports tolerated while other work removes them: none today (the re-mapping job and the
# place-index cache left common/mosaic for common/mosaic_upkeep, issue 19). An entry is
# (kind, from, to): kind "include" is folder → folder, kind "link" is target → target.
ALLOWED_UPWARD = [
]

# Files over MAX_FILE_LINES in areas other engineers are changing now: none today (issue 19 split
# the last ones, relocalization's dense place search and relocalizer). An entry is file → current
# length in lines; the check fails if a file grows past it (and reports the entry stale once it is
# short enough).
ALLOWED_LONG_FILES = {
}

# Functions over MAX_FUNCTION_LINES in the same areas: "file:function" → the current lengths
# of the functions of that name there (overloads), longest first.
ALLOWED_LONG_FUNCTIONS = {
}

TEST_ONLY_FILES = {"common/runtime/notify_listener.cpp", "common/runtime/notify_listener.h"}
SOURCE_DIRS = ["common", "services", "tools"]
SOURCE_EXTS = (".cpp", ".h", ".hpp", ".cc")


def is_test_file(rel):
    base = os.path.basename(rel)
    stem = os.path.splitext(base)[0]
    return (rel.startswith("tests/") or stem.endswith("_test") or "_test_util" in stem
            or stem.endswith("_fixture") or rel in TEST_ONLY_FILES)


def source_files(root):
    out = []
    for top in SOURCE_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
            for name in sorted(filenames):
                if name.endswith(SOURCE_EXTS):
                    out.append(os.path.relpath(os.path.join(dirpath, name), root))
    return out


def read(root, rel):
    with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
        return f.read()


# ---------------------------------------------------------------------------------------------
# Lexing: blank out comments, literals and preprocessor lines, keeping every newline.

def token_before(text, i):
    """The identifier or number ending just before text[i]."""
    k = i - 1
    while k >= 0 and (text[k].isalnum() or text[k] in "_."):
        k -= 1
    return text[k + 1:i]


def literal_end(text, i):
    """The end (exclusive) of the string or character literal opening at text[i]; a literal
    left open ends with its line."""
    quote = text[i]
    j = i + 1
    while j < len(text) and text[j] != quote and text[j] != "\n":
        j += 2 if text[j] == "\\" else 1
    return j + 1 if j < len(text) and text[j] == quote else min(j, len(text))


def blank_code(text):
    """Returns text with comments, string/char/raw-string literals and preprocessor directives
    replaced by spaces (newlines kept, so offsets map to the same lines)."""
    out = list(text)
    n = len(text)
    i = 0
    line_start = True  # only whitespace so far on this line

    def blank(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if c == "\n":
            line_start = True
            i += 1
            continue
        if line_start and c == "#":
            j = i
            while j < n:  # the directive, with its continuation lines and comments
                if text[j] == "\\" and j + 1 < n and text[j + 1] == "\n":
                    j += 2
                    continue
                if text.startswith("/*", j):
                    end = text.find("*/", j + 2)
                    j = n if end < 0 else end + 2
                    continue
                if text[j] == "\n":
                    break
                j += 1
            blank(i, j)
            i = j
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            j = n if end < 0 else end + 2
            blank(i, j)
            i = j
            continue
        if c == '"':
            # Raw string: R"delim( ... )delim", with an optional u8/u/U/L prefix before the R.
            if token_before(text, i) in ("R", "u8R", "uR", "UR", "LR"):
                open_paren = text.find("(", i + 1)
                delim = text[i + 1:open_paren]
                end = text.find(")" + delim + '"', open_paren + 1)
                j = n if end < 0 else end + len(delim) + 2
                blank(i, j)
                i = j
                continue
            j = literal_end(text, i)
            blank(i, j)
            i = j
            continue
        if c == "'":
            # A digit separator (1'000'000, 0xFF'FF) when the token before starts with a digit.
            if token_before(text, i)[:1].isdigit():
                i += 1
                continue
            j = literal_end(text, i)
            blank(i, j)
            i = j
            continue
        i += 1
    return "".join(out)


# ---------------------------------------------------------------------------------------------
# Function bodies.

SCOPE_KEYWORDS = re.compile(r"^(?:template\s*<.*>\s*)?(?:typedef\s+)?"
                            r"(namespace|class|struct|union|enum|extern)\b", re.S)
TRAILING_QUALIFIERS = re.compile(
    r"(?:\s*(?:const|volatile|noexcept\s*(?:\([^()]*\))?|noexcept|override|final|mutable|"
    r"constexpr|&&|&|->\s*[\w:<>,\s*&\[\]]+|requires\s+[\w:<>,\s]+))*\s*$")
CONTROL = re.compile(r"(?:^|[^\w])(if|for|while|switch|catch|do|else|return|try)\s*$")
CTOR_INIT = re.compile(r"\)\s*(?:noexcept\s*)?:(?!:)")


def top_level(header, chars):
    """Positions of the given characters in header outside (), [], <> nesting."""
    depth = 0
    found = []
    for k, ch in enumerate(header):
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif ch in chars and depth == 0:
            found.append(k)
    return found


def without_operators(header):
    """header with `operator==` and the like as `operator_` (their = and () are no syntax)."""
    return re.sub(r"\boperator\s*(?:\(\)|[^\s(]+)", "operator_", header.strip())


def function_name(header):
    h = header.strip()
    m = re.search(r"((?:[~\w:]*::)?operator\s*(?:\(\)|[^\s(]+)|[~\w:]+)\s*\(", h)
    eq = top_level(without_operators(h), "=")
    if eq:  # a lambda bound to a name
        lhs = without_operators(h)[:eq[-1]].split()
        return lhs[-1] if lhs else "lambda"
    return m.group(1) if m else "?"


def opens_function(header):
    """Whether a brace after `header` (at namespace or class scope) opens a function body."""
    h = without_operators(header)
    if not h or SCOPE_KEYWORDS.match(h):
        return False
    if CTOR_INIT.search(h) and h[-1] in ")}":
        return True  # a constructor's initializer list ends
    eq = top_level(h, "=")
    if eq:  # a lambda bound at namespace scope, otherwise an initializer
        rhs = h[eq[-1] + 1:].strip()
        return rhs.startswith("[")
    h = TRAILING_QUALIFIERS.sub("", h)
    if CONTROL.search(h):
        return False
    return h.endswith(")")


def functions(code):
    """[(start_line, end_line, name)] of the function bodies in blanked code (1-based lines)."""
    result = []
    # Stack of scopes: "ns" (namespace, class or extern: functions may start here), "fn",
    # "other" (initializers, enums: nothing inside is a function we measure).
    stack = []
    header_start = None
    header_chars = []
    n = len(code)
    i = 0
    line = 1
    fn_start = []  # for each open "fn": (start_line, name)

    def reset_header():
        nonlocal header_start, header_chars
        header_start = None
        header_chars = []

    while i < n:
        c = code[i]
        if c == "\n":
            line += 1
            header_chars.append(" ")
            i += 1
            continue
        in_fn = any(s == "fn" for s in stack)
        if c == "{":
            if in_fn:
                stack.append("inner")
            else:
                header = "".join(header_chars)
                prev = header.rstrip()[-1:] if header.strip() else ""
                if (CTOR_INIT.search(header) and (prev.isalnum() or prev in "_>")
                        and not opens_function(header)):
                    # A member's brace initializer inside a constructor's initializer list:
                    # part of the header. Skip to its closing brace.
                    depth = 0
                    j = i
                    while j < n:
                        if code[j] == "{":
                            depth += 1
                        elif code[j] == "}":
                            depth -= 1
                            if depth == 0:
                                break
                        elif code[j] == "\n":
                            line += 1
                        j += 1
                    header_chars.append(" {} ")
                    i = j + 1
                    continue
                if stack and stack[-1] == "other":
                    stack.append("other")
                elif opens_function(header):
                    stack.append("fn")
                    fn_start.append((header_start if header_start else line,
                                     function_name(header)))
                elif SCOPE_KEYWORDS.match(header.strip()) and not re.match(
                        r"^(?:template\s*<.*>\s*)?enum\b", header.strip(), re.S):
                    stack.append("ns")
                else:
                    stack.append("other")
            reset_header()
            i += 1
            continue
        if c == "}":
            if stack:
                kind = stack.pop()
                if kind == "fn":
                    start, name = fn_start.pop()
                    result.append((start, line, name))
            if not any(s == "fn" for s in stack):
                reset_header()
            i += 1
            continue
        if c == ";" and not in_fn:
            # A declaration ends (or a statement of an initializer: harmless).
            depth = header_chars.count("(") - header_chars.count(")")
            if depth <= 0:
                reset_header()
                i += 1
                continue
        if not in_fn:
            if header_start is None and not c.isspace():
                header_start = line
            header_chars.append(c)
        i += 1
    return result


# ---------------------------------------------------------------------------------------------
# Layers.

def folder_of(rel):
    parts = rel.split("/")
    return "/".join(parts[:2]) if len(parts) > 2 else None


def layer_table():
    table = {}
    for rank, (_, folders) in enumerate(LAYERS):
        for folder in folders:
            table[folder] = rank
    return table


def resolve_include(root, rel, target):
    """The folder an #include names ("common/x", "services/y", "tools/z"), or None (system,
    generated or same-folder headers)."""
    first = target.split("/")[0]
    if "/" not in target:
        return None
    for top in SOURCE_DIRS:
        if os.path.isdir(os.path.join(root, top, first)):
            return top + "/" + first
    return None


INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def include_offences(root, files, layers):
    found = {}  # (from_folder, to_folder) -> [file:line]
    for rel in files:
        if is_test_file(rel):
            continue
        src = folder_of(rel)
        if src not in layers:
            continue
        text = read(root, rel)
        for m in INCLUDE.finditer(text):
            dst = resolve_include(root, rel, m.group(1))
            if dst is None or dst == src or dst not in layers:
                continue
            if layers[dst] > layers[src]:
                line = text.count("\n", 0, m.start()) + 1
                found.setdefault((src, dst), []).append("%s:%d (%s)" % (rel, line, m.group(1)))
    return found


def cmake_targets(root):
    """{target: folder} of add_library/add_executable, and [(folder, target, [links])] of
    target_link_libraries, from every CMakeLists.txt under the source folders."""
    defined = {}
    links = []
    for top in SOURCE_DIRS:
        for dirpath, _, filenames in os.walk(os.path.join(root, top)):
            if "CMakeLists.txt" not in filenames:
                continue
            rel_dir = os.path.relpath(dirpath, root)
            folder = folder_of(rel_dir + "/x")
            text = re.sub(r"#[^\n]*", "", read(root, os.path.join(rel_dir, "CMakeLists.txt")))
            for m in re.finditer(r"\b(?:add_library|add_executable)\s*\(\s*([\w-]+)", text):
                defined[m.group(1)] = folder
            for m in re.finditer(r"\btarget_link_libraries\s*\(([^)]*)\)", text):
                words = m.group(1).split()
                links.append((folder, words[0],
                              [w for w in words[1:] if w not in ("PUBLIC", "PRIVATE",
                                                                 "INTERFACE")]))
    return defined, links


def link_offences(root, layers):
    defined, links = cmake_targets(root)
    found = {}
    for folder, target, deps in links:
        if target.endswith("_test") or target not in defined:
            continue
        src_layer = layers.get(defined[target])
        for dep in deps:
            if dep not in defined or src_layer is None:
                continue
            dst_layer = layers.get(defined[dep])
            if dst_layer is not None and dst_layer > src_layer:
                found.setdefault((target, dep), []).append(folder + "/CMakeLists.txt")
    return found


# ---------------------------------------------------------------------------------------------

def check(root, out=sys.stdout):
    """Runs every rule; prints a report; returns the number of failures."""
    failures = 0
    layers = layer_table()
    files = source_files(root)

    def say(msg):
        print(msg, file=out)

    # 1. Layers.
    unknown = sorted({folder_of(f) for f in files if folder_of(f) not in layers})
    for folder in unknown:
        say("layer: %s has no layer (add it to LAYERS in %s)" % (folder, __file__))
        failures += 1
    offences = {("include",) + k: v for k, v in include_offences(root, files, layers).items()}
    offences.update({("link",) + k: v for k, v in link_offences(root, layers).items()})
    allowed = set(ALLOWED_UPWARD)
    for key in sorted(offences):
        status = "allowed" if key in allowed else "OFFENCE"
        if key not in allowed:
            failures += 1
        say("upward %s %s: %s -> %s (%s over %s)" % (
            key[0], status, key[1], key[2], layer_name(key[2], layers, root),
            layer_name(key[1], layers, root)))
        for where in offences[key]:
            say("    " + where)
    for key in sorted(allowed - set(offences)):
        say("upward %s STALE allow-list entry: %s -> %s no longer happens; remove it" % key)
        failures += 1

    # 2. File length; 3. function length.
    long_files = {}
    long_functions = {}
    function_count = 0
    for rel in files:
        if is_test_file(rel):
            continue
        text = read(root, rel)
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        if lines > MAX_FILE_LINES:
            long_files[rel] = lines
        for start, end, name in functions(blank_code(text)):
            function_count += 1
            length = end - start + 1
            if length > MAX_FUNCTION_LINES:
                long_functions.setdefault("%s:%s" % (rel, name), []).append((start, length))

    for rel, lines in sorted(long_files.items()):
        limit = ALLOWED_LONG_FILES.get(rel)
        ok = limit is not None and lines <= limit
        failures += 0 if ok else 1
        say("file %s: %s has %d lines (max %d%s)" % (
            "allowed" if ok else "OFFENCE", rel, lines, MAX_FILE_LINES,
            "" if limit is None else ", allowed up to %d" % limit))
    for rel in sorted(set(ALLOWED_LONG_FILES) - set(long_files)):
        say("file STALE allow-list entry: %s is no longer over %d lines; remove it" % (
            rel, MAX_FILE_LINES))
        failures += 1

    for key, found in sorted(long_functions.items()):
        limits = sorted(ALLOWED_LONG_FUNCTIONS.get(key, []), reverse=True)
        for rank, (start, length) in enumerate(sorted(found, key=lambda f: -f[1])):
            limit = limits[rank] if rank < len(limits) else None
            ok = limit is not None and length <= limit
            failures += 0 if ok else 1
            rel, name = key.split(":", 1)
            say("function %s: %s:%d %s is %d lines (max %d%s)" % (
                "allowed" if ok else "OFFENCE", rel, start, name, length, MAX_FUNCTION_LINES,
                "" if limit is None else ", allowed up to %d" % limit))
    for key, limits in sorted(ALLOWED_LONG_FUNCTIONS.items()):
        if len(long_functions.get(key, [])) < len(limits):
            say("function STALE allow-list entry: %s has fewer than %d functions over %d lines;"
                " shorten its list" % (key, len(limits), MAX_FUNCTION_LINES))
            failures += 1

    say("check_structure: %d files, %d functions measured; %d upward imports (%d allowed), "
        "%d long files, %d long functions; %d failures" % (
            len(files), function_count, len(offences), len(allowed & set(offences)),
            len(long_files), sum(len(v) for v in long_functions.values()), failures))
    return failures


def layer_name(folder_or_target, layers, root):
    if folder_or_target in layers:
        return LAYERS[layers[folder_or_target]][0]
    defined, _ = cmake_targets(root)
    folder = defined.get(folder_or_target)
    return LAYERS[layers[folder]][0] if folder in layers else "?"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    args = parser.parse_args()
    return 1 if check(os.path.abspath(args.root)) else 0


if __name__ == "__main__":
    sys.exit(main())
