#!/usr/bin/env python3
"""Generate a URDF chain of N links for the URDF growth benchmark.

Usage: gen_urdf_chain.py N OUT.urdf [--one-line]

Links l0..l{N-1}, fixed joints j1..j{N-1} (l{k-1} -> l{k}), each with an
origin xyz="0.01 0.002 -0.003" rpy="0.001 -0.002 0.003" so the composed
chain is not trivial. --one-line writes the whole robot on one line, as a
`robot_description` parameter dump is.
"""
import sys

n = int(sys.argv[1])
out = sys.argv[2]
sep = "" if "--one-line" in sys.argv[3:] else "\n"
parts = ['<?xml version="1.0"?>', '<robot name="chain">']
for k in range(n):
    parts.append(f'<link name="l{k}"/>')
for k in range(1, n):
    parts.append(
        f'<joint name="j{k}" type="fixed"><parent link="l{k-1}"/><child link="l{k}"/>'
        '<origin xyz="0.01 0.002 -0.003" rpy="0.001 -0.002 0.003"/></joint>'
    )
parts.append("</robot>")
with open(out, "w") as f:
    f.write(sep.join(parts) + "\n")
