#!/usr/bin/env python3
"""Rewrites the help blocks of doc/cli/*.md from the programs' own --help.

A help block is a fenced block holding "-h,--help"; its program is the one named as
`PROGRAM --help` in the text just before it, or `pyramid NAME` for doc/cli/pyramid-NAME.md.
The block keeps the help from its "Positionals:" or "Options:" line on.

    python3 scripts/doc-help.py [--check] [BUILD_DIR]      (default: build)

With --check nothing is written: each block that differs from its program's help is named,
and the exit status is 1 (ctest runs this as doc_help_blocks).
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
args = sys.argv[1:]
check = "--check" in args
args = [a for a in args if a != "--check"]
bin_dir = root / (args[0] if args else "build") / "cli"
stale = []


def help_text(command):
    out = subprocess.run([str(bin_dir / command[0])] + command[1:] + ["--help"], capture_output=True, text=True,
                         check=True).stdout
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line in ("Positionals:", "Options:"))
    return "\n".join(line.rstrip() for line in lines[start:]).rstrip() + "\n"


for page in sorted((root / "doc" / "cli").glob("*.md")):
    text = page.read_text()
    parts = re.split(r"(```\n.*?```\n)", text, flags=re.S)
    changed = False
    for k in range(1, len(parts), 2):
        if "-h,--help" not in parts[k]:
            continue
        named = re.findall(r"`(\w+) --help`", parts[k - 1])
        if named:
            command = [named[-1]]
        elif page.stem.startswith("pyramid-"):
            command = ["pyramid", page.stem[len("pyramid-"):]]
        else:
            continue
        block = "```\n" + help_text(command) + "```\n"
        if block != parts[k]:
            parts[k] = block
            changed = True
            stale.append(f"{page.relative_to(root)}: the help block of `{' '.join(command)}` differs from its --help")
    if changed and not check:
        page.write_text("".join(parts))
        print("updated", page.relative_to(root))

if check and stale:
    print("\n".join(stale) + "\n(python3 scripts/doc-help.py rewrites them)", file=sys.stderr)
    sys.exit(1)
