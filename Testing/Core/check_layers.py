#!/usr/bin/env python3
"""The core's layers (Filters/Core/tetdsr/README.md, the line "Layers, lowest first: ...") are
one-way: each file includes only core files of its own layer or of a layer before it. Every file
sits in a named layer, and every include names an existing core file. Exit status 1 names each
file and include that breaks this."""
import os
import re
import sys

CORE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Filters", "Core")


def main():
    root = os.path.join(CORE, "tetdsr")
    page = open(os.path.join(root, "README.md"), encoding="utf-8").read()
    match = re.search(r"^Layers, lowest first: (.+)$", page, re.M)
    if not match:
        print("Filters/Core/tetdsr/README.md: no line 'Layers, lowest first: ...'")
        return 1
    order = [name.strip() for name in match.group(1).split(",")]
    rank = {name: i for i, name in enumerate(order)}
    problems, files = [], 0
    for layer in sorted(os.listdir(root)):
        path = os.path.join(root, layer)
        if not os.path.isdir(path):
            if not layer.endswith(".md"):
                problems.append(f"tetdsr/{layer}: a source outside every layer")
            continue
        if layer not in rank:
            problems.append(f"tetdsr/{layer}/: a folder the page's layer line does not name")
            continue
        for name in sorted(os.listdir(path)):
            files += 1
            text = open(os.path.join(path, name), encoding="utf-8").read()
            for inc in re.findall(r'#include\s+"tetdsr/([^"]+)"', text):
                target = inc.split("/")[0]
                if not os.path.isfile(os.path.join(root, inc)):
                    problems.append(f"tetdsr/{layer}/{name} includes tetdsr/{inc}: no such file")
                elif target not in rank or rank[target] > rank[layer]:
                    problems.append(f"tetdsr/{layer}/{name} ({layer}) includes tetdsr/{inc} "
                                    f"({target}): a later layer")
    for problem in problems:
        print(problem)
    print(f"{files} files in {len(order)} layers ({', '.join(order)}): {len(problems)} problems")
    return 1 if problems or files == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
