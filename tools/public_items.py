#!/usr/bin/env python3
"""Count the public items of the library as rustdoc documents them.

Usage: tools/public_items.py [DOC_DIR]   (default target/doc/extrinsic_audit)

Run after `cargo doc --no-deps --lib` (add RUSTDOCFLAGS=--document-hidden-items
to count hidden items too, `internals` among them). Counted the same way at any
commit:
- items: the entries of rustdoc's all.html (structs, enums, traits, functions,
  type aliases, constants, statics, macros, ...), each item once at its
  canonical path, plus the module pages (one index.html per public module);
- associated: on each item page, public fields and enum variants, and the
  methods and associated constants of inherent impls (everything before the
  "Trait Implementations" section; derived and blanket trait methods are not
  counted), and a trait's own methods.
"""
import pathlib
import re
import sys

doc = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "target/doc/extrinsic_audit")
all_html = (doc / "all.html").read_text()
kinds = {}
for kind, body in re.findall(r'<h3 id="([a-z-]+)">.*?</h3><ul class="all-items">(.*?)</ul>', all_html, re.S):
    kinds[kind] = body.count("<li>")
modules = sum(1 for p in doc.rglob("index.html"))
assoc = {"fields": 0, "variants": 0, "methods": 0, "constants": 0}
for page in doc.rglob("*.html"):
    name = page.name
    if not re.match(r"(struct|enum|union|trait)\.", name):
        continue
    text = page.read_text()
    head = re.split(r'id="(?:trait-implementations|implementors|synthetic-implementations|blanket-implementations)"', text)[0]
    assoc["fields"] += len(set(re.findall(r'id="structfield\.([A-Za-z0-9_]+)"', head)))
    assoc["variants"] += len(set(re.findall(r'id="variant\.([A-Za-z0-9_]+)"', head)))
    assoc["methods"] += len(set(re.findall(r'id="(?:ty)?method\.([A-Za-z0-9_]+)"', head)))
    assoc["constants"] += len(set(re.findall(r'id="associatedconstant\.([A-Za-z0-9_]+)"', head)))
items = sum(kinds.values()) + modules
print("items:", items, "=", ", ".join(f"{k} {v}" for k, v in kinds.items()), f", modules {modules}")
print("associated:", sum(assoc.values()), "=", ", ".join(f"{k} {v}" for k, v in assoc.items()))
print("total:", items + sum(assoc.values()))
