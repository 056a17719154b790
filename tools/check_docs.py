#!/usr/bin/env python3
"""Checks that the docs name only what exists.

For README.md, docs/*.md and each folder's README.md:
  - every repository path they mention (in `backticks`, links or images, or in a
    code block) exists: a file or folder of the source tree, a header named the
    way code includes it (`earshot/...`), or, for `build/release/...`, a file of
    the build tree given with --build;
  - every `earshot ...` command they show (in code blocks and in `backticks`)
    exists: `earshot SUBCOMMAND... --help` exits 0 and lists every --option the
    doc gives it; the same for `tools/*.py` scripts; `scripts/*.sh` are
    executable files.

Prints one line per problem (file:line: what) and exits 1 if there is any, 2 on
bad arguments. Usage:
  tools/check_docs.py --root SRC --build BUILD --earshot BUILD/apps/earshot
"""
import argparse
import glob
import os
import re
import shlex
import subprocess
import sys

# The repository's own top-level folders (read from the tree, so a new folder is
# covered the day it lands), and .ci. Paths beginning with one are checked.
def top_folders(root):
    tracked = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True)
    if tracked.returncode == 0 and tracked.stdout:
        tops = {f.split("/")[0] for f in tracked.stdout.splitlines() if "/" in f}
    else:  # not a git checkout: the folders on disk
        tops = {d for d in os.listdir(root) if os.path.isdir(os.path.join(root, d))}
    return sorted(d for d in tops if not d.startswith(".") and not d.startswith("build")) + [".ci"]


def path_re(top):
    return re.compile(r"(?<![\w./-])((?:\./)?(?:%s|build/release)/[\w./*{},+-]*[\w*}])" %
                      "|".join(re.escape(t) for t in top))


INCLUDE_RE = re.compile(r"(?<![\w./-])(earshot/[\w/]+\.(?:h|hpp))\b")
MD_RE = re.compile(r"`([\w.-]+\.md)`")
FENCE_RE = re.compile(r"^\s*```")
TICK_RE = re.compile(r"`([^`]+)`")
LINK_RE = re.compile(r"\]\(([^)#\s]+)\)")


class Checker:
    def __init__(self, root, build, earshot):
        self.root, self.build, self.earshot = root, build, earshot
        self.path_re = path_re(top_folders(root))
        self.problems = []
        self.help_cache = {}

    def problem(self, where, what):
        self.problems.append(f"{where}: {what}")

    # ---- the README's layout ---------------------------------------------------
    def check_layout(self, readme):
        """README.md's "Layout" section names every top-level folder as `folder/`."""
        text = open(readme).read()
        m = re.search(r"^## Layout\n(.*?)(?=^## )", text, re.S | re.M)
        if not m:
            self.problem(os.path.basename(readme), "no '## Layout' section naming the folders")
            return
        for top in top_folders(self.root):
            if f"`{top}/`" not in m.group(1):
                self.problem(os.path.basename(readme), f"the Layout section does not name `{top}/`")

    # ---- paths -------------------------------------------------------------
    def path_exists(self, p):
        p = p.rstrip(".,;:)")
        if p.startswith("./"):
            p = p[2:]
        if p.startswith("build/release/"):
            if not self.build:
                return True  # no build tree given: not checked
            full = os.path.join(self.build, p[len("build/release/"):])
        else:
            full = os.path.join(self.root, p)
        if "{" in full:  # a{b,c}: each alternative must exist
            m = re.search(r"\{([^}]*)\}", full)
            return all(self.path_exists_abs(full[:m.start()] + alt + full[m.end():])
                       for alt in m.group(1).split(","))
        return self.path_exists_abs(full)

    @staticmethod
    def path_exists_abs(full):
        if any(c in full for c in "*?["):
            return bool(glob.glob(full))
        return os.path.exists(full)

    def include_exists(self, inc):
        return bool(glob.glob(os.path.join(self.root, "*", "include", inc)) or
                    glob.glob(os.path.join(self.root, "*", "*", "include", inc)))

    def check_paths(self, where, text):
        for m in self.path_re.finditer(text):
            p = m.group(1)
            if p.endswith("/") or "..." in p or "PATH" in p or "NAME" in p:
                continue
            if not self.path_exists(p):
                self.problem(where, f"no such path: {p}")
        for m in MD_RE.finditer(text):  # another doc named by its file name alone
            name = m.group(1)
            if "/" not in name and not (os.path.exists(os.path.join(self.root, name)) or
                                        os.path.exists(os.path.join(self.root, "docs", name))):
                self.problem(where, f"no such document in the repository: {name}")
        for m in INCLUDE_RE.finditer(text):
            if not self.include_exists(m.group(1)):
                self.problem(where, f"no such header: {m.group(1)}")

    # ---- commands ----------------------------------------------------------
    def help_text(self, argv):
        key = tuple(argv)
        if key not in self.help_cache:
            try:
                r = subprocess.run(argv + ["--help"], capture_output=True, text=True, timeout=30,
                                   cwd=self.root)
                self.help_cache[key] = (r.returncode, r.stdout + r.stderr)
            except (OSError, subprocess.TimeoutExpired) as e:
                self.help_cache[key] = (-1, str(e))
        return self.help_cache[key]

    def check_earshot(self, where, words):
        """words: the tokens after `earshot`."""
        sub = []
        for w in words:
            if not re.fullmatch(r"[a-z][a-z-]*", w):
                break
            sub.append(w)
        if not sub:
            return
        # The longest prefix of words that the program knows as subcommands.
        while sub:
            code, text = self.help_text([self.earshot] + sub)
            # An unknown word gets the parent's help: the usage line tells.
            usage = re.search(r"^Usage: \S*earshot((?: [a-z][a-z-]*)*)", text, re.M)
            if code == 0 and usage and usage.group(1).split() == sub:
                break
            sub.pop()
        if not sub:
            self.problem(where, f"unknown command: earshot {' '.join(words[:2])}")
            return
        self.check_options(where, "earshot " + " ".join(sub), words, text)

    def check_options(self, where, name, words, text):
        for w in words:
            for opt in re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", w):
                if opt == "--help":
                    continue
                if not re.search(r"(?<![\w-])%s(?![\w-])" % re.escape(opt), text):
                    self.problem(where, f"`{name}` has no option {opt}")

    def check_command(self, where, line):
        line = line.strip()
        if line.startswith("$ "):
            line = line[2:]
        line = line.split("#", 1)[0] if " #" in line else line
        try:
            words = shlex.split(line, comments=False)
        except ValueError:
            words = line.split()
        if not words:
            return
        head = words[0]
        if head.startswith("EARSHOT_") and "=" in head:  # VAR=value command
            words = words[1:]
            if not words:
                return
            head = words[0]
        if head == "earshot" or head.endswith("/apps/earshot"):
            if self.earshot:
                self.check_earshot(where, words[1:])
        elif head in ("python3", "/usr/bin/python3") and len(words) > 1 and words[1].startswith("tools/"):
            script = os.path.join(self.root, words[1])
            if not os.path.exists(script):
                self.problem(where, f"no such tool: {words[1]}")
                return
            # The interpreter the doc names (Debian's, which has matplotlib) when here.
            python = head if os.access(head, os.X_OK) else sys.executable
            code, text = self.help_text([python, script])
            if code != 0:
                self.problem(where, f"`{words[1]} --help` exits {code}")
            else:
                self.check_options(where, words[1], words[2:], text)
        elif re.fullmatch(r"(\./)?scripts/[\w.-]+", head):
            full = os.path.join(self.root, head.removeprefix("./"))
            if not os.access(full, os.X_OK):
                self.problem(where, f"not an executable script: {head}")

    # ---- documents ---------------------------------------------------------
    def check_file(self, path):
        rel = os.path.relpath(path, self.root)
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        in_code, pending = False, None
        for n, line in enumerate(lines, 1):
            where = f"{rel}:{n}"
            if FENCE_RE.match(line):
                if in_code and pending:  # the block's last command
                    self.check_command(*pending)
                in_code = not in_code
                pending = None
                continue
            self.check_paths(where, line)
            if in_code:
                # A usage line continued on the next lines ("   [--x]"): one command.
                if pending and re.match(r"^\s+[\[-]", line):
                    pending[1] += " " + line.strip()
                    continue
                if pending:
                    self.check_command(*pending)
                pending = [where, line]
            else:
                for m in LINK_RE.finditer(line):
                    target = m.group(1)
                    if "://" in target or target.startswith("mailto:"):
                        continue
                    full = os.path.normpath(os.path.join(os.path.dirname(path), target))
                    if not os.path.exists(full):
                        self.problem(where, f"broken link: {target}")
                for m in TICK_RE.finditer(line):
                    span = m.group(1)
                    if re.match(r"^(\./)?(earshot|build/release/apps/earshot|scripts/)[ /]", span + " "):
                        self.check_command(where, span)
            if not in_code and pending:
                self.check_command(*pending)
                pending = None
        if pending:
            self.check_command(*pending)


def default_docs(root):
    """README.md, docs/*.md and the README.md of every folder (build trees aside)."""
    docs = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))
    for top in top_folders(root):
        for d, subdirs, files in os.walk(os.path.join(root, top)):
            subdirs[:] = sorted(x for x in subdirs if not x.startswith("build"))
            if "README.md" in files and d != root:
                docs.append(os.path.join(d, "README.md"))
    return docs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", required=True, help="the source tree")
    ap.add_argument("--build", help="the Release build tree (build/release/... paths are checked in it)")
    ap.add_argument("--earshot", help="the earshot executable (commands are checked with --help)")
    ap.add_argument("docs", nargs="*", help="Markdown files (default: README.md, docs/*.md and every "
                                            "folder's README.md)")
    a = ap.parse_args()
    if not os.path.isdir(a.root):
        print(f"check_docs: --root {a.root}: not a folder", file=sys.stderr)
        return 2
    if a.earshot and not os.access(a.earshot, os.X_OK):
        print(f"check_docs: --earshot {a.earshot}: not an executable", file=sys.stderr)
        return 2
    docs = a.docs or default_docs(a.root)
    c = Checker(os.path.abspath(a.root), a.build and os.path.abspath(a.build),
                a.earshot and os.path.abspath(a.earshot))
    for d in docs:
        if not os.path.exists(d):
            print(f"check_docs: {d}: no such file", file=sys.stderr)
            return 2
        c.check_file(d)
    if not a.docs:
        c.check_layout(os.path.join(a.root, "README.md"))
    for p in c.problems:
        print(p)
    print(f"check_docs: {len(docs)} files, {len(c.help_cache)} commands run, {len(c.problems)} problems")
    return 1 if c.problems else 0


if __name__ == "__main__":
    sys.exit(main())
