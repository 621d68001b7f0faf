#!/usr/bin/env python3
"""The test-data folder for scripts: the same lookup as tests/it/common/testdata.rs.

The folder is $EXTRINSIC_AUDIT_TEST_DATA, else shared/test-data beside the
checkout; its MANIFEST.tsv lists each third-party file (path in the folder,
repository, commit, path in the repository, sha256, licence). Where the folder
has no MANIFEST.tsv, the table of docs/test-data.md stands in.

    tools/testdata.py path NAME...   print each file's path, sha256 checked
                                     (exit 3, with what to fetch, if absent)
    tools/testdata.py root           print the folder
    tools/testdata.py list [PREFIX]  print the folder's paths (under PREFIX)
    tools/testdata.py table          rewrite the table of docs/test-data.md
                                     from MANIFEST.tsv

From Python: sys.path.insert(0, "<checkout>/tools"); import testdata;
testdata.find(NAME) (None if absent).
"""

import hashlib
import os
import sys

CHECKOUT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENV = "EXTRINSIC_AUDIT_TEST_DATA"
DOC = os.path.join(CHECKOUT, "docs", "test-data.md")
BEGIN, END = "<!-- table:begin -->", "<!-- table:end -->"
COLUMNS = ("path", "repository", "commit", "path_in_repo", "sha256", "licence")


def root():
    return os.environ.get(ENV) or os.path.normpath(os.path.join(CHECKOUT, "..", "shared", "test-data"))


def read_manifest(path):
    rows = []
    with open(path, encoding="utf-8") as f:
        next(f)
        for line in f:
            if not line.strip():
                continue
            c = line.rstrip("\n").split("\t")
            assert len(c) == 7, f"{path}: 7 columns expected, found {line!r}"
            rows.append(dict(zip(("project_path",) + COLUMNS, [c[0], c[1].removeprefix("test-data/")] + c[2:])))
    return rows


def read_doc_table():
    rows = []
    with open(DOC, encoding="utf-8") as f:
        text = f.read()
    table = text[text.index(BEGIN) + len(BEGIN):text.index(END)]
    for line in table.splitlines():
        if line.startswith("| `"):
            c = [x.strip() for x in line.strip().strip("|").split(" | ")]
            rows.append(dict(zip(COLUMNS, [x.strip("`") for x in c[:5]] + [c[5]])))
    return rows


def manifest():
    m = os.path.join(root(), "MANIFEST.tsv")
    return read_manifest(m) if os.path.isfile(m) else read_doc_table()


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def find(name):
    """The verified path of NAME (a path in the folder, or the old project path); None if absent."""
    n = name.removeprefix("test-data/")
    rows = manifest()
    e = next((r for r in rows if r["path"] == n), None) or next(
        (r for r in rows if r.get("project_path") == n), None
    )
    if e is None:
        sys.exit(f"{name}: not in the test-data manifest ({DOC})")
    p = os.path.join(root(), e["path"])
    if not os.path.isfile(p):
        print(
            f"skipped: needs {e['path']} from the test-data folder {root()} (not there): "
            f"{e['repository']} at commit {e['commit']}, path {e['path_in_repo']} "
            f"(the manifest: MANIFEST.tsv in that folder, or docs/test-data.md; override: {ENV})",
            file=sys.stderr,
        )
        return None
    got = sha256(p)
    if got != e["sha256"]:
        sys.exit(f"{p}: sha256 {got}, the manifest says {e['sha256']}: a different file")
    return p


# The real robot descriptions by the names the URDF fixtures give them (the
# file names they had in tests/fixtures/urdf; tests/it/common/testdata.rs, URDFS).
URDFS = {
    "anymal_c.urdf": "Gepetto__example-robot-data/robots/anymal_c_simple_description/urdf/anymal.urdf",
    "anymal_d.urdf": "ANYbotics__anymal_d_simple_description/urdf/anymal.urdf",
    "pr2.urdf": "Gepetto__example-robot-data/robots/pr2_description/urdf/pr2.urdf",
    "tiago_pro.urdf": "Gepetto__example-robot-data/robots/tiago_pro_description/robots/tiago_pro.urdf",
    "turtlebot3_burger.urdf": "ROBOTIS-GIT__turtlebot3/turtlebot3_description/urdf/turtlebot3_burger.urdf",
    "turtlebot3_waffle.urdf": "ROBOTIS-GIT__turtlebot3/turtlebot3_description/urdf/turtlebot3_waffle.urdf",
    "unitree_b2.urdf": "unitreerobotics__unitree_ros/robots/b2_description/urdf/b2_description.urdf",
    "unitree_g1_29dof.urdf": "unitreerobotics__unitree_ros/robots/g1_description/g1_29dof.urdf",
    "unitree_go2.urdf": "unitreerobotics__unitree_ros/robots/go2_description/urdf/go2_description.urdf",
    "unitree_h1.urdf": "unitreerobotics__unitree_ros/robots/h1_description/urdf/h1.urdf",
}


def need(name):
    """find(NAME), or exit naming what to fetch: for fixture generators."""
    p = find(name)
    if p is None:
        sys.exit(f"{name}: needed from the test-data folder (docs/test-data.md)")
    return p


def urdf(name):
    """A URDF fixture by name: a real robot of URDFS (needed), else tests/fixtures/urdf/NAME."""
    if name in URDFS:
        return need(URDFS[name])
    return os.path.join(CHECKOUT, "tests", "fixtures", "urdf", name)


def table():
    rows = read_manifest(os.path.join(root(), "MANIFEST.tsv"))
    seen, lines = set(), ["| file | repository | commit | path in repository | sha256 | licence |", "|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: r["path"].lower()):
        if r["path"] in seen:
            continue
        seen.add(r["path"])
        lines.append("| " + " | ".join([f"`{r[c]}`" for c in COLUMNS[:5]] + [r["licence"]]) + " |")
    with open(DOC, encoding="utf-8") as f:
        text = f.read()
    a, b = text.index(BEGIN) + len(BEGIN), text.index(END)
    with open(DOC, "w", encoding="utf-8") as f:
        f.write(text[:a] + "\n" + "\n".join(lines) + "\n" + text[b:])
    print(f"{DOC}: {len(seen)} files")


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    cmd = argv[1]
    if cmd == "root":
        print(root())
    elif cmd == "path":
        paths = [find(n) for n in argv[2:]]
        if None in paths:
            sys.exit(3)
        print("\n".join(paths))
    elif cmd == "list":
        prefix = argv[2].rstrip("/") + "/" if len(argv) > 2 else ""
        print("\n".join(sorted({r["path"] for r in manifest() if r["path"].startswith(prefix)})))
    elif cmd == "table":
        table()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
