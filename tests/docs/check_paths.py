#!/usr/bin/env python3
"""Checks that every repository path README.md and docs/**/*.md name exists.

Usage: check_paths.py [REPO_ROOT]   (default: two folders above this script)

What counts as a named path:
  - the target of every Markdown link or image, [text](target) and ![alt](target), outside
    code: relative to the folder of the file that holds it (the repository root for README.md);
  - every token with a '/' inside inline code (`...`) or a fenced code block, when its first
    component is an entry of the repository root (or, in docs/, of the Markdown file's own
    folder), or when it starts with '../'. In docs/ such a token may be relative to either.
    A glob (*, ?, [) must match at least one file.

Left alone: URLs and anchors (the part after '#' too), absolute paths (/tmp, JSON pointers such
as /leaks/0/rate), anything under runs/, data/ or build/ (outputs, not sources), placeholders
(DIR, RUN/last.pt, OUT/, river_caseN.json, fluid_NNNNN.ply, <run>, {md,json}, ...), tokens with
'=' or '$', command options, the output a command is told to write (the token after --out,
--save-data or --work), and bare file names without a '/' (spill.json, trajectory.h5,
metadata.json are what a command writes into a run folder).

Also holds the README to a map's length: at most README_MOST_LINES lines (the figures and the
details live in docs/, the README points at them).

Prints what it checked and exits 1 listing every named path that does not exist, or naming the
README's length when it is over. Python 3 standard library only.
"""
import glob
import os
import re
import sys

SKIPPED_TOP = {"runs", "data", "build"}
README_MOST_LINES = 300
OUTPUT_OPTIONS = {"--out", "--save-data", "--work"}
# Characters stripped from the ends of a token taken from code (a leading '.' is kept: ../x).
LEADING_PUNCTUATION = "\"'`(["
TRAILING_PUNCTUATION = "\"'`)],;:.!?"
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
INLINE_CODE = re.compile(r"(`+)(.+?)(?<!`)\1(?!`)", re.DOTALL)
FENCE = re.compile(r"^\s*(```|~~~)")
ALL_CAPS = re.compile(r"^[A-Z][A-Z0-9_]*$")  # DIR, RUN, OUT, T1, F10, C_WEIGHTS
CAPS_SUFFIX = re.compile(r"[a-z0-9_][A-Z]+$")  # river_caseN, fluid_NNNNN
DOCUMENT_EXTENSIONS = {"md", "txt", "rst"}


def is_placeholder(path):
    if any(c in path for c in "<>{}$|") or "..." in path:
        return True
    for part in path.split("/"):
        stem, _, extension = part.partition(".")
        if extension in DOCUMENT_EXTENSIONS:
            continue  # README.md, DESIGN.md: capitals by convention, not placeholders
        if stem and (ALL_CAPS.match(stem) or CAPS_SUFFIX.search(stem)):
            return True
    return False


def inside(root, path):
    root = os.path.abspath(root)
    path = os.path.abspath(path)
    return path == root or path.startswith(root + os.sep)


def exists(path):
    if any(c in path for c in "*?["):
        return bool(glob.glob(path))
    return os.path.exists(path)


class Checker:
    def __init__(self, root):
        self.root = os.path.abspath(root)
        self.top = set(os.listdir(self.root)) - SKIPPED_TOP
        self.checked = 0
        self.missing = []  # (file, line, path, why)

    def report(self, md, line, path, why):
        self.missing.append((os.path.relpath(md, self.root), line, path, why))

    # A path from a link: relative to the Markdown file's folder.
    def check_link(self, md, line, target):
        if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("#"):
            return  # URL, mailto:, anchor
        path = target.split("#")[0].split("?")[0]
        if not path or path.startswith("/") or is_placeholder(path):
            return
        full = os.path.normpath(os.path.join(os.path.dirname(md), path))
        rel = os.path.relpath(full, self.root)
        if rel.split(os.sep)[0] in SKIPPED_TOP:
            return
        self.checked += 1
        if not inside(self.root, full):
            self.report(md, line, target, "outside the repository")
        elif not exists(full):
            self.report(md, line, target, "no such file or folder")

    # A token from inline code or a code block.
    def check_token(self, md, line, token):
        token = token.lstrip(LEADING_PUNCTUATION).rstrip(TRAILING_PUNCTUATION)
        if "/" not in token or token.startswith(("/", "~", "-")) or "://" in token:
            return
        if "=" in token or "$" in token:
            return
        if ":" in token:
            if token.index(":") < token.index("/"):
                return  # 10:F10/comparison.json, a mapping rather than a path
            token = token[: token.index(":")]  # file.json:/json/pointer
            token = token.rstrip(TRAILING_PUNCTUATION)
        if token.startswith("./"):
            token = token[2:]
        if is_placeholder(token):
            return
        here = os.path.dirname(md)
        in_docs = os.path.abspath(here) != self.root
        first = token.split("/")[0]
        if first == "..":
            bases = [here]
        else:
            bases = []
            if first in self.top:
                bases.append(self.root)
            if in_docs and first in set(os.listdir(here)) - SKIPPED_TOP:
                bases.append(here)
            if not bases:
                return  # not a repository path: an output folder, a unit, a ratio
        candidates = [os.path.normpath(os.path.join(b, token)) for b in bases]
        rels = [os.path.relpath(c, self.root).split(os.sep)[0] for c in candidates]
        if any(r in SKIPPED_TOP for r in rels):
            return
        self.checked += 1
        if not any(inside(self.root, c) for c in candidates):
            self.report(md, line, token, "outside the repository")
        elif not any(inside(self.root, c) and exists(c) for c in candidates):
            self.report(md, line, token, "no such file or folder")

    def check_code(self, md, first_line, text):
        previous = ""
        for offset, line_text in enumerate(text.split("\n")):
            for token in line_text.split():
                if previous not in OUTPUT_OPTIONS:
                    self.check_token(md, first_line + offset, token)
                previous = token  # kept across lines: an option's value may wrap

    def check_file(self, md):
        with open(md, encoding="utf-8") as f:
            lines = f.read().split("\n")
        prose = []  # (line number, text) outside fenced blocks
        in_fence = False
        fence_start = 0
        fence_lines = []
        for number, text in enumerate(lines, 1):
            if FENCE.match(text):
                if in_fence:
                    self.check_code(md, fence_start + 1, "\n".join(fence_lines))
                    fence_lines = []
                else:
                    fence_start = number
                in_fence = not in_fence
                prose.append((number, ""))
                continue
            if in_fence:
                fence_lines.append(text)
                prose.append((number, ""))
            else:
                prose.append((number, text))
        text = "\n".join(t for _, t in prose)

        def line_of(offset):
            return text.count("\n", 0, offset) + 1

        # Inline code spans (they may wrap over lines), then links in what is left.
        def blank(match):
            self.check_code(md, line_of(match.start()), match.group(2))
            return re.sub(r"[^\n]", " ", match.group(0))

        rest = INLINE_CODE.sub(blank, text)
        for match in LINK.finditer(rest):
            self.check_link(md, line_of(match.start()), match.group(1))


def markdown_files(root):
    files = [os.path.join(root, "README.md")]
    for folder, dirs, names in os.walk(os.path.join(root, "docs")):
        dirs.sort()
        files += [os.path.join(folder, n) for n in sorted(names) if n.endswith(".md")]
    return files


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    if not os.path.isfile(os.path.join(root, "README.md")):
        print(f"check_paths: error: {root}: no README.md (expected the repository root)")
        return 2
    checker = Checker(root)
    files = markdown_files(checker.root)
    for md in files:
        checker.check_file(md)
    print(f"check_paths: {checker.checked} paths named in {len(files)} Markdown files checked")
    with open(os.path.join(root, "README.md"), encoding="utf-8") as f:
        readme_lines = len(f.read().splitlines())
    too_long = readme_lines > README_MOST_LINES
    if too_long:
        print(f"README.md: {readme_lines} lines, over the {README_MOST_LINES} a map may have: "
              "move details and figures to docs/ and point at them")
    if checker.missing:
        for md, line, path, why in sorted(checker.missing):
            print(f"{md}:{line}: {path}: {why}")
        print(f"check_paths: {len(checker.missing)} named paths do not exist")
        return 1
    return 1 if too_long else 0


if __name__ == "__main__":
    sys.exit(main())
