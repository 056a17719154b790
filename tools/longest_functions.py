#!/usr/bin/env python3
"""Lists the longest functions of the libraries and apps (not tests).

Parses every source file of a build tree's compile_commands.json that lies in
one of the project's library or app folders (or every unity batch that holds one) with libclang (Debian's
python3-clang-14) and prints the function bodies defined there, longest
first, as lines from the opening to the closing brace:

  tools/longest_functions.py build/release            # the 15 longest
  tools/longest_functions.py build/release --top 40 --min 60

Exits 2 on bad arguments or when libclang cannot be loaded.
"""
import argparse
import glob
import json
import multiprocessing
import os
import sys

FOLDERS = ("apps", "audio", "common", "host", "hrtf", "lv2", "plugin", "scenes", "tracker", "webcam", "ambisonics", "head")
# Lambdas are counted inside the function that holds them.
KINDS = ("FUNCTION_DECL", "CXX_METHOD", "CONSTRUCTOR", "DESTRUCTOR", "FUNCTION_TEMPLATE", "CONVERSION_FUNCTION")


def load_clang():
    try:
        import clang.cindex as ci
    except ImportError:
        sys.path.append("/usr/lib/python3/dist-packages")
        import clang.cindex as ci
    for lib in sorted(glob.glob("/usr/lib/x86_64-linux-gnu/libclang-*.so*") + glob.glob("/usr/lib/llvm-*/lib/libclang*.so*")):
        try:
            ci.Config.set_library_file(lib)
            ci.Index.create()
            return ci
        except Exception:
            ci.Config.loaded = False
    ci.Index.create()
    return ci


def source_dir(build):
    """The source tree the build tree was configured from (its CMakeCache)."""
    with open(os.path.join(build, "CMakeCache.txt")) as f:
        for line in f:
            if line.startswith("CMAKE_HOME_DIRECTORY:"):
                return line.split("=", 1)[1].strip()
    return os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def ours(path, root):
    """A source in the project's folders, or a unity batch (EARSHOT_UNITY_BUILD) that includes one."""
    if os.path.relpath(path, root).split(os.sep)[0] in FOLDERS:
        return True
    if os.path.basename(os.path.dirname(path)) != "Unity":
        return False
    with open(path) as f:
        for line in f:
            if line.startswith("#include"):
                inc = line.split('"')[1] if '"' in line else ""
                if inc and os.path.relpath(os.path.abspath(inc), root).split(os.sep)[0] in FOLDERS:
                    return True
    return False


def qualified(c):
    parts = []
    while c is not None and c.kind.name != "TRANSLATION_UNIT":
        if c.spelling:
            parts.append(c.spelling)
        c = c.semantic_parent
    return "::".join(reversed(parts))


def functions_in(job):
    """(file, line, kind, lines, name) of each function body defined in the project's folders."""
    path, args, root = job
    ci = load_clang()
    try:
        tu = ci.Index.create().parse(path, args=args + ["-Wno-everything"])
    except ci.TranslationUnitLoadError:
        print(f"longest_functions: {path}: libclang cannot parse it; skipped", file=sys.stderr)
        return []
    out = []
    for c in tu.cursor.walk_preorder():
        try:
            kind = c.kind.name
        except ValueError:  # a cursor kind newer than these bindings
            continue
        if kind not in KINDS or not c.is_definition():
            continue
        loc = c.extent.start
        if loc.file is None:
            continue
        f = os.path.relpath(os.path.abspath(loc.file.name), root)
        if f.split(os.sep)[0] not in FOLDERS:
            continue
        body = [ch for ch in c.get_children() if ch.kind == ci.CursorKind.COMPOUND_STMT]
        if body:
            out.append((f, loc.line, kind, body[-1].extent.end.line - body[-1].extent.start.line + 1, qualified(c)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", help="a build tree with compile_commands.json")
    ap.add_argument("--top", type=int, default=15, help="how many to print (default 15)")
    ap.add_argument("--min", type=int, default=0, help="print only functions of at least this many lines")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="files parsed at once (default: all cores)")
    a = ap.parse_args()
    cc = os.path.join(a.build, "compile_commands.json")
    if not os.path.isfile(cc):
        print(f"longest_functions: {cc}: no such file (configure the tree first)", file=sys.stderr)
        return 2
    try:
        load_clang()
    except Exception as e:
        print(f"longest_functions: cannot load libclang ({e}); install python3-clang-14", file=sys.stderr)
        return 2
    root = source_dir(a.build)
    jobs, seen = [], set()
    for entry in json.load(open(cc)):
        path = os.path.abspath(os.path.join(entry["directory"], entry["file"]))
        if path in seen or not path.endswith((".cpp", ".cc", ".c", ".cxx")) or not ours(path, root):
            continue
        seen.add(path)
        args = entry.get("arguments") or entry["command"].split()
        args = [x for x in args[1:] if x not in ("-c", entry["file"], path)]
        if "-o" in args:
            i = args.index("-o")
            del args[i:i + 2]
        jobs.append((path, args, root))
    found = {}
    with multiprocessing.Pool(a.jobs) as pool:
        for rows in pool.imap_unordered(functions_in, jobs):
            for f, line, kind, n, name in rows:
                found[(f, line, kind)] = (n, name)
    rows = sorted(((n, name, f, line) for (f, line, _), (n, name) in found.items() if n >= a.min), reverse=True)
    print(f"{'lines':>5}  function  (file:line)")
    for n, name, f, line in rows[:a.top]:
        print(f"{n:5}  {name}  ({f}:{line})")
    print(f"longest_functions: {len(found)} functions in {len(jobs)} files")
    return 0


if __name__ == "__main__":
    sys.exit(main())
