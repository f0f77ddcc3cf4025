#!/usr/bin/env python3
"""Writes crates/penumbra/src/bsdf/ior_table.rs: the measured conductor
indices Mitsuba 3 ships, reduced to linear sRGB as Mitsuba 3's RGB variants
reduce them when a scene names a `material`.

Source data: the `ior/<name>.eta.spd` and `ior/<name>.k.spd` files of the
mitsuba-data repository (https://github.com/mitsuba-renderer/mitsuba-data),
measured optical constants from the Luxpop database (Palik; LLNL-CXRO),
the same data pbrt ships. Every pair of files found is one material.

The reduction (Mitsuba's `spectrum_list_to_srgb` with `bounded` and `d65`
both off, in double precision, as `complex_ior_from_file` calls it):

- 1000 wavelengths evenly spaced from 360 nm to 830 nm, both included;
  a wavelength outside the file's first and last one contributes nothing;
- the spectrum interpolated linearly between the file's two neighbouring
  wavelengths;
- the CIE 1931 2-degree colour matching functions every 5 nm from 360 nm
  (95 values, single precision), interpolated linearly;
- the sum times 470 / 1000 / 106.7502593994140625 (a constant, so that a
  unit spectrum has luminance close to 1), with no illuminant;
- XYZ to linear sRGB (Rec. 709 primaries, D65 white), negative channels
  set to 0, and the result rounded to single precision.

Usage: python3 scripts/conductor_ior.py IOR_DIR [COMMIT] > crates/penumbra/src/bsdf/ior_table.rs
where IOR_DIR is the `ior` folder of a mitsuba-data checkout and COMMIT the
commit it was taken from (written in the file's header).

Plain Python, no dependencies. `python3 scripts/conductor_ior.py --check`
prints the RGB of a few test spectra instead (a flat 1 with and without the
D65 weighting), to compare with Penumbra's own reduction.
"""

import os
import struct
import sys

CIE_MIN, CIE_MAX, STEPS = 360.0, 830.0, 1000
Y_NORMALIZATION = 1.0 / 106.7502593994140625
D65_NORMALIZATION = 1.0 / 98.99741751876255


def f32(x):
    """x rounded to the nearest single-precision number."""
    return struct.unpack("f", struct.pack("f", x))[0]


def f32_text(x):
    """The shortest decimal text that reads back as the single-precision x."""
    x = f32(x)
    for digits in range(1, 10):
        text = "%.*g" % (digits, x)
        if f32(float(text)) == x:
            break
    if "e" not in text and "." not in text:
        text += ".0"
    return text


def cie_table_path():
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.join(
        here, "..", "crates", "penumbra", "src", "description", "mitsuba", "cie_table.rs"
    )


def load_cie():
    """x̄, ȳ, z̄, D65 every 5 nm, from Penumbra's table of the CIE data,
    each rounded to single precision as Mitsuba stores them."""
    rows = []
    with open(cie_table_path()) as f:
        for line in f:
            line = line.strip()
            if line.startswith("[") and line.endswith("nm"):
                values = line[1 : line.index("]")].split(",")
                rows.append([f32(float(v)) for v in values])
    assert len(rows) == 95, len(rows)
    return rows


CIE = load_cie()


def interpolate_table(w, column):
    t = (w - CIE_MIN) * (94 / (CIE_MAX - CIE_MIN))
    i0 = min(max(int(t), 0), 93)
    w1 = t - i0
    w0 = 1.0 - w1
    return w0 * CIE[i0][column] + w1 * CIE[i0 + 1][column]


def srgb(wavelengths, values, bounded, d65):
    """Mitsuba's `spectrum_list_to_srgb` in double precision."""
    xyz = [0.0, 0.0, 0.0]
    for i in range(STEPS):
        w = CIE_MIN + (i / (STEPS - 1)) * (CIE_MAX - CIE_MIN)
        if w < wavelengths[0] or w > wavelengths[-1]:
            continue
        # The last index j in [0, n-2] with wavelengths[j] <= w.
        j = 0
        while j + 1 < len(wavelengths) - 1 and wavelengths[j + 1] <= w:
            j += 1
        w0, w1 = wavelengths[j], wavelengths[j + 1]
        v0, v1 = values[j], values[j + 1]
        v = ((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1)
        if CIE_MIN <= w <= CIE_MAX:
            weight = interpolate_table(w, 3) * D65_NORMALIZATION if d65 else 1.0
            for c in range(3):
                xyz[c] += interpolate_table(w, c) * v * weight
    scale = (CIE_MAX - CIE_MIN) * Y_NORMALIZATION / STEPS
    xyz = [c * scale for c in xyz]
    m = [
        [3.240479, -1.537150, -0.498535],
        [-0.969256, 1.875991, 0.041556],
        [0.055648, -0.204043, 1.057311],
    ]
    m = [[f32(e) for e in row] for row in m]
    rgb = [row[0] * xyz[0] + row[1] * xyz[1] + row[2] * xyz[2] for row in m]
    if bounded:
        rgb = [min(max(c, 0.0), 1.0) for c in rgb]
    else:
        rgb = [max(c, 0.0) for c in rgb]
    return rgb


def read_spd(path):
    """A .spd file as Mitsuba reads it: per line, `#` starts a comment, the
    first number is a wavelength in nm and the second a value."""
    wavelengths, values = [], []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            if not line:
                continue
            if len(line) != 2:
                raise SystemExit(f"{path}: expected two numbers, got {line}")
            wavelengths.append(float(line[0]))
            values.append(float(line[1]))
    if len(wavelengths) < 2 or any(b <= a for a, b in zip(wavelengths, wavelengths[1:])):
        raise SystemExit(f"{path}: wavelengths must increase")
    return wavelengths, values


def rgb_text(rgb):
    return "[" + ", ".join(f32_text(c) for c in rgb) + "]"


def main():
    if sys.argv[1:2] == ["--check"]:
        flat = ([360.0, 830.0], [1.0, 1.0])
        print("flat 1, d65:   ", [f32(c) for c in srgb(*flat, False, True)])
        print("flat 1, no d65:", [f32(c) for c in srgb(*flat, False, False)])
        return
    if len(sys.argv) not in (2, 3):
        raise SystemExit(__doc__)
    folder = sys.argv[1]
    commit = sys.argv[2] if len(sys.argv) == 3 else "unknown"
    names = sorted(
        f[: -len(".eta.spd")] for f in os.listdir(folder) if f.endswith(".eta.spd")
    )
    out = sys.stdout
    out.write(
        "// Generated by scripts/conductor_ior.py from the ior/*.spd files of\n"
        f"// mitsuba-data (commit {commit}); do not edit.\n"
        "\n"
        "/// Every measured conductor of Mitsuba 3's data, by name (byte order):\n"
        "/// `eta` and `k` of `ior/<name>.eta.spd` and `ior/<name>.k.spd` reduced\n"
        "/// to linear sRGB as Mitsuba 3's RGB variants reduce them (see the\n"
        "/// [module docs](self)).\n"
        "#[rustfmt::skip]\n"
        f"pub const MEASURED: [(&str, [f32; 3], [f32; 3]); {len(names)}] = [\n"
    )
    for name in names:
        eta = srgb(*read_spd(os.path.join(folder, name + ".eta.spd")), False, False)
        k = srgb(*read_spd(os.path.join(folder, name + ".k.spd")), False, False)
        out.write(f'    ("{name}", {rgb_text(eta)}, {rgb_text(k)}),\n')
    out.write("];\n")


if __name__ == "__main__":
    main()
