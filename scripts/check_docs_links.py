#!/usr/bin/env python3
"""Checks that every relative link in the Markdown documentation, and every
citation of a documentation page in the code's comments, resolves to a file
(and, with #anchor, to a heading of that file).

Usage: scripts/check_docs_links.py [REPO_ROOT]

Links checked: [text](target), ![alt](target) and <img src="target"> in
README.md, CHANGELOG.md and docs/**/*.md (docs/paper/README.md is generated
and checked too); and `docs/NAME.md` or `docs/NAME.md#anchor` written in the
sources (core, apps, plugins, python, scripts, tests, cmake). Anchors are
GitHub's: the heading's text, lower case, with punctuation dropped and spaces
turned into hyphens (a repeated heading gets -1, -2, ...). Links to web
addresses are not checked. Exit status 0 when all resolve, 1 otherwise, with
one line per broken link naming the file and line.
"""
import os
import re
import sys

# Pages that other pages link to while they are being written elsewhere: a
# missing one is reported as pending, not as broken. Once present, links into
# them are checked like any other.
PENDING = {
    "docs/reference/manifest.md",
    "docs/topics/cellml_import.md",
    "docs/topics/cellml_units.md",
    "docs/dev/build_types.md",
    "docs/topics/cellml_corpus.md",
}

# Links written by a program into output kept as it was written (the
# figure these ladders drew was not kept): reported as known, not as broken.
KNOWN = {
    ("docs/accuracy/strand_colman_lookup_tables/with_tables.md", "work_precision.png"),
    ("docs/accuracy/strand_colman_lookup_tables/without_tables.md", "work_precision.png"),
}

MD_LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
IMG_SRC = re.compile(r"<img\s[^>]*src=\"([^\"]+)\"")
CODE_CITATION = re.compile(r"(?<![\w/.-])(docs/[\w./-]+\.md(?:#[\w-]+)?)")
SOURCE_DIRS = ["core", "apps", "plugins", "python", "scripts", "tests", "cmake"]
SOURCE_EXT = (".cpp", ".hpp", ".h", ".py", ".pyi", ".sh", ".cmake", ".txt", ".in")


def slug(heading):
    text = re.sub(r"<[^>]+>", "", heading)  # inline HTML
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links: their text
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path, cache={}):
    if path not in cache:
        found, counts, fence = set(), {}, False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.lstrip().startswith("```"):
                    fence = not fence
                    continue
                m = None if fence else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
                if not m:
                    continue
                s = slug(m.group(1))
                n = counts.get(s, 0)
                counts[s] = n + 1
                found.add(s if n == 0 else f"{s}-{n}")
        cache[path] = found
    return cache[path]


def markdown_files(root):
    files = [os.path.join(root, f) for f in ("README.md", "CHANGELOG.md") if os.path.exists(os.path.join(root, f))]
    for d, _, names in os.walk(os.path.join(root, "docs")):
        files += [os.path.join(d, n) for n in names if n.endswith(".md")]
    return sorted(files)


def links_in_markdown(path):
    fence = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if line.lstrip().startswith("```"):
                fence = not fence
                continue
            if fence:
                continue
            for m in list(MD_LINK.finditer(line)) + list(IMG_SRC.finditer(line)):
                yield number, m.group(1)


def citations_in_sources(root):
    for top in SOURCE_DIRS:
        for d, _, names in os.walk(os.path.join(root, top)):
            for n in names:
                if not n.endswith(SOURCE_EXT):
                    continue
                path = os.path.join(d, n)
                if os.path.abspath(path) == os.path.abspath(__file__):
                    continue
                with open(path, encoding="utf-8", errors="replace") as f:
                    for number, line in enumerate(f, 1):
                        for m in CODE_CITATION.finditer(line):
                            yield path, number, m.group(1)


def check(root, source, number, target, base_dir, problems, pending):
    if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
        return
    file_part, _, anchor = target.partition("#")
    resolved = os.path.normpath(os.path.join(base_dir, file_part)) if file_part else source
    relative = os.path.relpath(resolved, root)
    where = f"{os.path.relpath(source, root)}:{number}"
    if not os.path.exists(resolved):
        if (os.path.relpath(source, root), target) in KNOWN:
            pending.add(f"{where}: {target} (known: output kept as written, without its figure)")
        elif relative in PENDING:
            pending.add(f"{where}: {target} (pending: {relative} is being written elsewhere)")
        else:
            problems.append(f"{where}: {target}: no file {relative}")
        return
    if anchor:
        if not resolved.endswith(".md"):
            problems.append(f"{where}: {target}: an anchor into a file that is not Markdown")
        elif anchor not in anchors_of(resolved):
            problems.append(f"{where}: {target}: no heading with anchor #{anchor} in {relative}")


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    problems, pending, count = [], set(), 0
    for path in markdown_files(root):
        for number, target in links_in_markdown(path):
            count += 1
            check(root, path, number, target, os.path.dirname(path), problems, pending)
    for path, number, target in citations_in_sources(root):
        count += 1
        check(root, path, number, target, root, problems, pending)
    for p in sorted(pending):
        print("not checked:", p)
    for p in problems:
        print("broken:", p)
    print(f"{count} links checked, {len(problems)} broken, {len(pending)} pending or known")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
