#!/usr/bin/env python3
"""Write a scenario of N elastic balls (discs in 2D, spheres in 3D) dropped
into a rigid open box under gravity, with one [general_contact] table.

The balls stand in layers (a row of `--across` in 2D, a square of
`--across` × `--across` in 3D), every other layer shifted by a sixth of the
spacing; the box is as wide as a layer and high enough for all of them.

    python3 scripts/make_pour.py --dim 3 --count 100 -o pour.toml
    conserve run pour.toml
"""
import argparse
import math
import sys

MATERIAL = """[body.material]
young = 1.0e6
poisson = 0.3
density = 1000.0
"""


def wall(name, translate, dims, size, dim):
    pos = ", ".join(f"{v:.4f}" for v in translate)
    if dim == 2:
        mesh = f'generator = "rectangle"\nlx = {dims[0]:.4f}\nly = {dims[1]:.4f}\nsize = {size:.4f}\n'
    else:
        mesh = (f'generator = "box"\nlx = {dims[0]:.4f}\nly = {dims[1]:.4f}\nlz = {dims[2]:.4f}\n'
                f"size = {size:.4f}\n")
    return f'[[body]]\nname = "{name}"\nrigid = true\ntranslate = [{pos}]\n[body.mesh]\n{mesh}'


def scenario(dim, count, across, radius, size, speed, step, end):
    spacing = 2.5 * radius
    per_layer = across if dim == 2 else across * across
    layers = math.ceil(count / per_layer)
    width = (across + 1 / 3) * spacing  # room for the layers' shifts
    height = (layers + 1) * spacing + 2 * radius
    t = 2 * size  # wall thickness
    out = [f"# {count} elastic {'discs' if dim == 2 else 'spheres'} (R = {radius * 1e3:g} mm, E = 1 MPa) "
           f"dropped at {speed:g} m/s into a rigid box\n"
           f"# under gravity, every body against every body and itself by one [general_contact] table.\n"
           f"# Written by scripts/make_pour.py --dim {dim} --count {count} --across {across}.\n"
           f'title = "{count} {"discs" if dim == 2 else "spheres"} poured into a box"\n'
           f"dimension = {dim}\n\n[time]\nstep = {step:g}\nend = {end:g}\n\n[output]\nvtu_every = 10\n\n"
           f"[loads]\ngravity = {[0.0, -9.81] if dim == 2 else [0.0, 0.0, -9.81]}\n\n[general_contact]\n"]
    up = dim - 1  # the vertical axis, the last

    def at(horizontal, vertical):
        return list(horizontal) + [vertical]

    floor_dims = [width + 2 * t] * (dim - 1) + [t]
    out.append(wall("floor", at([0.0] * (dim - 1), -t / 2), floor_dims, size * 4, dim))
    sides = [("left", 0, -1), ("right", 0, 1)] + ([("front", 1, -1), ("back", 1, 1)] if dim == 3 else [])
    for name, axis, sign in sides:
        centre = [0.0] * (dim - 1)
        centre[axis] = sign * (width / 2 + t / 2)
        dims = [width + 2 * t] * (dim - 1)
        dims[axis] = t
        dims.append(height)
        out.append(wall(name, at(centre, height / 2), dims, size * 4, dim))
    velocity = [0.0] * dim
    velocity[up] = -speed
    k = 0
    for layer in range(layers):
        shift = (spacing / 6) * (1 if layer % 2 else -1)
        for cell in range(per_layer):
            if k == count:
                break
            i, j = cell % across, cell // across
            horizontal = [(i + 0.5 - across / 2) * spacing + shift]
            if dim == 3:
                horizontal.append((j + 0.5 - across / 2) * spacing - shift)
            pos = at(horizontal, radius + 0.25 * radius + layer * spacing)
            generator = "disc" if dim == 2 else "sphere"
            out.append(f'[[body]]\nname = "b{k}"\ntranslate = [{", ".join(f"{v:.4f}" for v in pos)}]\n'
                       f"velocity = [{', '.join(f'{v:g}' for v in velocity)}]\n{MATERIAL}[body.mesh]\n"
                       f'generator = "{generator}"\nradius = {radius:g}\nsize = {size:g}\n')
            k += 1
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dim", type=int, choices=(2, 3), default=3)
    ap.add_argument("--count", type=int, default=100, help="number of balls (≥ 1)")
    ap.add_argument("--across", type=int, default=0,
                    help="balls along each horizontal side of a layer (default: 10 in 2D, 5 in 3D)")
    ap.add_argument("--radius", type=float, default=0.012, help="ball radius [m]")
    ap.add_argument("--size", type=float, default=0.0, help="mesh size [m] (default R/2 in 2D, 2R/3 in 3D)")
    ap.add_argument("--speed", type=float, default=0.5, help="initial downward speed [m/s]")
    ap.add_argument("--step", type=float, default=1.0e-3, help="time step [s]")
    ap.add_argument("--end", type=float, default=0.05, help="end time [s]")
    ap.add_argument("-o", "--output", default="-", help="scenario file to write (default: standard output)")
    a = ap.parse_args()
    if a.count < 1 or a.radius <= 0 or a.step <= 0 or a.end <= 0 or a.across < 0:
        sys.exit("make_pour.py: --count, --radius, --step and --end must be positive")
    across = a.across or (10 if a.dim == 2 else 5)
    size = a.size or (a.radius / 2 if a.dim == 2 else 2 * a.radius / 3)
    text = scenario(a.dim, a.count, across, a.radius, size, a.speed, a.step, a.end)
    if a.output == "-":
        sys.stdout.write(text)
    else:
        with open(a.output, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
