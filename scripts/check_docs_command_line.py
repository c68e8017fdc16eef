#!/usr/bin/env python3
"""Checks that docs/reference/command_line.md documents the command line the
program declares: every subcommand has a row in the table of commands and a
section ("## NAME"; "### bench headline" for bench's own), every option that
`fibrodem NAME --help` lists appears in its section, and no usage line or
option table there gives an option the program does not take.

Usage: scripts/check_docs_command_line.py FIBRODEM_EXE [REPO_ROOT]
Exit status 0 when they agree, 1 otherwise, naming each difference.
"""
import os
import re
import subprocess
import sys


def help_of(exe, *words):
    out = subprocess.run([exe, *words, "--help"], capture_output=True, text=True, check=True).stdout
    return out


def listed(help_text, heading):
    """The first word of each line under HEADING: in CLI11's help."""
    words, inside = [], False
    for line in help_text.splitlines():
        if line.strip().lower() == heading.lower() + ":":
            inside = True
            continue
        if inside and not line.startswith(" "):
            inside = False
        if inside and line.strip():
            words.append(line.split()[0])
    return words


def options(help_text):
    found = []
    for word in listed(help_text, "Options"):
        for name in word.split(","):
            if name.startswith("--") and name != "--help":
                found.append(name)
    return found


def sections(doc):
    """Heading text -> its body, for ## and ### headings."""
    out, name, body = {}, None, []
    for line in doc.splitlines():
        m = re.match(r"^#{2,3} (.+)$", line)
        if m:
            if name:
                out[name] = "\n".join(body)
            name, body = m.group(1).strip(), []
        elif name:
            body.append(line)
    if name:
        out[name] = "\n".join(body)
    return out


def written_options(body, words, subcommands):
    """The --options the section gives this command: in its usage lines
    (those of `fibrodem WORDS ...` itself, not of a subcommand of it) and in
    the first column of its option tables."""
    found = set()
    for block in re.findall(r"```\n(.*?)```", body, re.S):
        for line in block.splitlines():
            tokens = line.split()
            n = len(words) + 1
            if tokens[:n] != ["fibrodem", *words] or (len(tokens) > n and tokens[n] in subcommands):
                continue
            found |= set(re.findall(r"(--[a-z][\w-]*)", line))
    for row in re.findall(r"^\| `([^|]*)` \|", body, re.M):
        found |= set(re.findall(r"(--[a-z][\w-]*)", row))
    return found


def main():
    exe = sys.argv[1]
    root = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..")
    doc = open(os.path.join(root, "docs", "reference", "command_line.md")).read()
    parts = sections(doc)
    problems = []
    commands = [[c] for c in listed(help_of(exe), "Subcommands")]
    bench_subcommands = listed(help_of(exe, "bench"), "Subcommands")
    commands += [["bench", c] for c in bench_subcommands]
    table = doc.split("\n## ")[0]
    for words in commands:
        name = " ".join(words)
        if len(words) == 1 and f"[`{name}`]" not in table:
            problems.append(f"the table of commands has no row for `{name}`")
        if name not in parts:
            problems.append(f"command_line.md has no section '{name}' for `fibrodem {name}`")
            continue
        body = parts[name]
        declared = set(options(help_of(exe, *words)))
        for opt in sorted(declared):
            if not re.search(re.escape(opt) + r"(?![\w-])", body):
                problems.append(f"`fibrodem {name}` takes {opt}, which its section in command_line.md omits")
        subcommands = bench_subcommands if words == ["bench"] else []
        for opt in sorted(written_options(body, words, subcommands) - declared):
            if opt.startswith("--benchmark_"):  # Google Benchmark's own, passed through
                continue
            problems.append(f"command_line.md gives `fibrodem {name}` {opt}, which it does not take")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
