#!/usr/bin/env python3
"""The user docs (README.md, docs/*.md) name no commits: they date their figures, and
Testing/Benchmark/results/provenance.md maps each date to its commit. Any word of 7 to 40 hex
digits that this repository resolves as a commit fails (checksums and other hex stay). Also every
relative link in those pages points at an existing file. Exit status 1 names each."""
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def is_commit(word):
    return subprocess.run(["git", "-C", ROOT, "cat-file", "-e", word + "^{commit}"],
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0


def main():
    if subprocess.run(["git", "-C", ROOT, "rev-parse"], stdout=subprocess.DEVNULL,
                      stderr=subprocess.DEVNULL).returncode != 0:
        print("not a git checkout: the commit check needs the repository's history")
        return 1
    pages = [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md")))
    problems = []
    for page in pages:
        name = os.path.relpath(page, ROOT)
        for number, line in enumerate(open(page, encoding="utf-8"), 1):
            for word in re.findall(r"\b[0-9a-f]{7,40}\b", line):
                if re.search(r"[a-f]", word) and is_commit(word):
                    problems.append(f"{name}:{number}: commit {word} (date the figure instead; "
                                    "its commit goes into Testing/Benchmark/results/provenance.md)")
            for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", line):
                if re.match(r"[a-z]+:", target):
                    continue
                if not os.path.exists(os.path.join(os.path.dirname(page), target)):
                    problems.append(f"{name}:{number}: link to {target}: no such file")
    for problem in problems:
        print(problem)
    print(f"{len(pages)} pages: {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
