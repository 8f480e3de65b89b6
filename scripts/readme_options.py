#!/usr/bin/python3
"""The README's table of -pd_ options is generated from the option schema (src/scene/schema_table.c) by
`pdimplicit -pd_help_markdown`. This script writes it between the two marker lines of README.md;
with --check it only compares, and exits 1 (printing the first difference) when README.md is out of date.

    scripts/readme_options.py            # after changing the schema: rewrite the table
    scripts/readme_options.py --check    # CTest readme_options
"""
import difflib
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.environ.get("PDIMPLICIT", os.path.join(ROOT, "build", "pdimplicit"))
README = os.path.join(ROOT, "README.md")
BEGIN = "<!-- option table: generated from src/scene/schema_table.c by scripts/readme_options.py; do not edit by hand -->"
END = "<!-- end of the generated option table -->"


def generated():
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    out = subprocess.run([EXE, "-pd_help_markdown"], capture_output=True, text=True, env=env, check=True).stdout
    return out.strip("\n").splitlines()


def main():
    with open(README) as f:
        lines = f.read().splitlines()
    if BEGIN not in lines or END not in lines:
        sys.exit("README.md has no generated option table (marker lines missing)")
    a, b = lines.index(BEGIN), lines.index(END)
    table = generated()
    if "--check" in sys.argv[1:]:
        if lines[a + 1:b] == table:
            print("ok   README.md's option table equals the one generated from the schema (%d lines)" % len(table))
            return
        diff = list(difflib.unified_diff(lines[a + 1:b], table, "README.md", "pdimplicit -pd_help_markdown", lineterm="", n=0))
        print("FAIL README.md's option table differs from the schema's; run scripts/readme_options.py\n" + "\n".join(diff[:12]))
        sys.exit(1)
    with open(README, "w") as f:
        f.write("\n".join(lines[:a + 1] + table + lines[b:]) + "\n")
    print("README.md: option table written (%d lines)" % len(table))


if __name__ == "__main__":
    main()
