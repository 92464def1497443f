#!/usr/bin/env python3
"""Radiance reference for isorad's daylight: illuminance and daylight factor
at points of an isorad scene under a CIE sky, computed with Radiance's
rtrace (an independent renderer). Python 3.11+, numpy; Radiance's oconv,
rtrace and gensky on PATH or under --radiance PREFIX (PREFIX/bin, and
PREFIX/lib for RAYPATH).

  python3 bench/daylight_radiance.py SCENE.toml --points P.csv --out R.csv
      [--json R.json] [--sky overcast|clear|intermediate|uniform|cie_general]
      [--cie-type 1..15] [--horizontal-illuminance 10000]
      [--sun-altitude DEG --sun-azimuth DEG] [--sun-normal-illuminance LUX]
      [--ground-reflectance 0.2] [--north 0,0,-1]
      [--horizon sharp|gensky] [--ab 12 --ad 8192 --as 0 --lw 0.01/ad]
      [--runs 2] [--opening X,Y,Z;X,Y,Z;X,Y,Z ... [--opening-glass TN]]
  python3 bench/daylight_radiance.py --self-test

Each sky parameter is taken from its flag if given, else from the scene
TOML's [sky] / [sun] tables, else from the defaults above (a sun position
is needed by every sky but overcast, uniform and cie_general type 5;
azimuth is clockwise from north, degrees). From the TOML, a missing [sun]
or normal_illuminance = 0 means no direct beam; on the command line,
clear and intermediate skies get gensky's own sun (+s / +i) unless
--sun-normal-illuminance is given (0 = none, gensky -s / -i).

The scene: OBJ faces become Radiance polygons (a non-planar face is cut
into a triangle fan), in a frame where Radiance's +Z is isorad's up (+y),
+Y is isorad's north and +X east = north x up (a rotation, so windings and
normals are kept; points and normals are rotated the same way). MTL Kd ->
`plastic` (no specularity, no roughness); Tf (its Rec. 709 luminance, as
isorad reads it, is the normal-incidence transmittance Tn) -> `glass` with
transmissivity tn = (sqrt(.8402528435+.0072522239 Tn^2)-.9166530661)
/.0036261119/Tn in all three channels (Radiance's glass: n = 1.52, Fresnel
angular dependence and the pane's inter-reflections); Ke -> `light` of
radiance Ke (W/sr/m^2).

The sky: gensky -ang ALT AZ (gensky's azimuth is degrees WEST OF SOUTH:
ours minus 180) with -c / +s -s / +i -i / -u, -B E_h/179 and -g rho, then
the usual `skyfunc glow` on a sky and a ground `source` of angle 180.
gensky's ground is rho (E_sky,h + E_sun,h) / pi, its sun counted even with
-s / -i unless -r 0 is given (the script adds -r 0 when there is no beam).
--horizon gensky uses gensky's skyfunc as it is (skybright.cal), whose sky
and ground are blended near the horizon (weights (Dz+1.01)^10 and
(Dz+1.01)^-10: about 2 % less sky 10 degrees above the horizon) and whose
clear / intermediate normalisation is a polynomial fit. --horizon sharp
(the default) keeps gensky's sun (its radiance set from
--sun-normal-illuminance at full precision) but replaces the sky function
by the same CIE formulas (written to isorad_sky.cal) with a sharp
horizon, the zenith radiance scaled so that the sky alone gives exactly
E_h on an unobstructed horizontal plane (numerical integral), and the
ground uniform at rho (E_h + E_sun,h) / pi: the CIE definitions, which
isorad's skies should match. cie_general (ISO 15469 / CIE S 011 types 1..15) exists only in
sharp mode.

rtrace -I -aa 0 (no ambient cache: every point is an independent Monte
Carlo estimate, -ad stratified samples at the first bounce, one path per
sample after it), -lr -16 with Russian roulette below -lw, -dt 0 -dc 1
-dj 0 (the sun is sampled at its centre), -st 0. Three traps, measured on
daylit_office: ambient super-samples (-as > 0) go where the first samples
differ most, and with noisy multi-bounce samples that adaptive choice
biases the result LOW (-ad 65536 -as 16384: -30 % at the back of the
office; -ad 8192 -as 2048: -8 %), so -as is 0 (in black rooms, where a
sample is the sky's exact value, -as is unbiased and only lowers noise);
-ab 7 misses about 2 % at the back of a room of these reflectances (-ab 12
and -ab 20 agree); and a first-bounce sample's path has weight about
rho/ad, so with -lw above 1/ad Russian roulette keeps only about rho/lw
multi-bounce paths whatever -ad is (with -lw 1e-5 the noise at the back of
the office stopped falling beyond -ad 32768), hence -lw 0.01/ad.
Irradiance x 179 lm/W (Radiance's and isorad's efficacy; RGB to one value
by Rec. 709, isorad's convention) = lux.

rtrace -u+ seeds its random numbers with the time in seconds: each run
starts in a new second and traces the points in a different order, so the
runs are independent; the result is their mean, and the noise figure is
the mean |run1 - run2| / mean(run1, run2) over the points (the standard
error of the mean of two runs is about 0.63 times that figure).

--opening (repeatable) names an unglazed opening as three corners (a
corner and its two neighbours, isorad coordinates): the sky component at
each point is then also integrated numerically over the openings' area
(Gauss-Legendre; d(omega) cos(theta) = cos(theta_p) cos(theta_o) dA / r^2,
the sun added where its direction passes an opening), for a black room
whose points see every opening whole. --opening-glass TN: the openings are
glazed; the integral then applies a clear pane's angular transmittance
(Fresnel at both faces for n = 1.52, absorption per pass from TN, the
pane's inter-reflections: the model behind the tn formula above). The per-point comparison with
Radiance goes into the CSV and JSON.

DF = 100 E / E_h, with E_h the unobstructed horizontal illuminance of the
sky alone as rendered (exactly --horizontal-illuminance in sharp mode).
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib

import numpy as np

LUMENS_PER_WATT = 179.0
REC709 = np.array([0.2126, 0.7152, 0.0722])
SUN_HALF_ANGLE_DEG = 0.25
SUN_SOLID_ANGLE = 2 * math.pi * (1 - math.cos(math.radians(SUN_HALF_ANGLE_DEG)))
UP = np.array([0.0, 1.0, 0.0])

# ISO 15469:2004 / CIE S 011/E:2003 standard general skies: a, b, c, d, e.
CIE_GENERAL = {
    1: (4.0, -0.70, 0.0, -1.0, 0.00),
    2: (4.0, -0.70, 2.0, -1.5, 0.15),
    3: (1.1, -0.8, 0.0, -1.0, 0.00),
    4: (1.1, -0.8, 2.0, -1.5, 0.15),
    5: (0.0, -1.0, 0.0, -1.0, 0.00),
    6: (0.0, -1.0, 2.0, -1.5, 0.15),
    7: (0.0, -1.0, 5.0, -2.5, 0.30),
    8: (0.0, -1.0, 10.0, -3.0, 0.45),
    9: (-1.0, -0.55, 2.0, -1.5, 0.15),
    10: (-1.0, -0.55, 5.0, -2.5, 0.30),
    11: (-1.0, -0.55, 10.0, -3.0, 0.45),
    12: (-1.0, -0.32, 10.0, -3.0, 0.45),
    13: (-1.0, -0.32, 16.0, -3.0, 0.30),
    14: (-1.0, -0.15, 16.0, -3.0, 0.30),
    15: (-1.0, -0.15, 24.0, -2.8, 0.15),
}
MODEL_CODE = {"clear": 1, "overcast": 2, "uniform": 3, "intermediate": 4, "cie_general": 5}
TOML_MODELS = {"cie_overcast": "overcast", "cie_clear": "clear",
               "cie_intermediate": "intermediate", "cie_general": "cie_general",
               "uniform": "uniform"}

SKY_CAL = """{ isorad_sky.cal, written by isorad's bench/daylight_radiance.py:
  CIE sky radiance with a sharp horizon.
  A1: 1 CIE clear, 2 CIE overcast, 3 uniform, 4 intermediate (Radiance's
      skybright.cal formula), 5 CIE general (arguments 7..11 = a b c d e)
  A2: radiance per unit of the relative luminance below, W/sr/m2
  A3: ground radiance, W/sr/m2
  A4 A5 A6: sun direction }
cosgamma = Dx*A4 + Dy*A5 + Dz*A6;
gamma = Acos(cosgamma);
zt = Acos(A6);
eta = Acos(Dz);
dz = max(Dz, 1e-6);
rclear = (.91 + 10*exp(-3*gamma) + .45*cosgamma*cosgamma) * (1 - exp(-.32/dz));
rovercast = 1 + 2*Dz;
runiform = 1;
rinter = ((1.35*sin(5.631-3.59*eta)+3.12)*sin(4.396-2.6*zt) + 6.37 - eta)
        * exp(gamma*-.563*((2.629-eta)*(1.562-zt)+.812));
rgeneral = (1 + arg(9)*(exp(arg(10)*gamma) - exp(arg(10)*PI/2)) + arg(11)*cosgamma*cosgamma)
        * (1 + arg(7)*exp(arg(8)/dz));
skybr = if(Dz, A2*select(A1, rclear, rovercast, runiform, rinter, rgeneral), A3);
"""


def fail(message):
    sys.exit(f"daylight_radiance: {message}")


# --------------------------------------------------------------------------
# Frames and sky luminance (numpy, independent of Radiance).

def frame(north):
    """isorad -> Radiance rotation: rows east, north, up (isorad vectors)."""
    n = np.asarray(north, dtype=float)
    n = n - UP * (n @ UP)
    if np.linalg.norm(n) < 1e-9:
        fail("--north must not be vertical")
    n /= np.linalg.norm(n)
    east = np.cross(n, UP)
    return np.array([east, n, UP])


def sun_vector(altitude_deg, azimuth_deg, rot):
    """The sun direction in isorad coordinates (azimuth clockwise from north)."""
    a, z = math.radians(altitude_deg), math.radians(azimuth_deg)
    east, north, up = rot
    return math.cos(a) * (math.sin(z) * east + math.cos(z) * north) + math.sin(a) * up


def relative_luminance(model, dz, cosgamma, sun_z, cie=None):
    """The sky's relative luminance for directions of zenith cosine dz > 0
    and cosine cosgamma to the sun (formulas as in SKY_CAL)."""
    dz = np.maximum(dz, 1e-6)
    cosgamma = np.clip(cosgamma, -1, 1)
    gamma = np.arccos(cosgamma)
    if model == "overcast":
        return 1 + 2 * dz
    if model == "uniform":
        return np.ones_like(dz)
    if model == "clear":
        return (0.91 + 10 * np.exp(-3 * gamma) + 0.45 * cosgamma**2) * (1 - np.exp(-0.32 / dz))
    if model == "intermediate":
        zt, eta = math.acos(sun_z), np.arccos(np.clip(dz, -1, 1))
        return (((1.35 * np.sin(5.631 - 3.59 * eta) + 3.12) * math.sin(4.396 - 2.6 * zt)
                 + 6.37 - eta) * np.exp(gamma * -0.563 * ((2.629 - eta) * (1.562 - zt) + 0.812)))
    if model == "cie_general":
        a, b, c, d, e = cie
        return ((1 + c * (np.exp(d * gamma) - math.exp(d * math.pi / 2)) + e * cosgamma**2)
                * (1 + a * np.exp(b / dz)))
    raise ValueError(model)


def gensky_skybright(params, dx, dy, dz):
    """Radiance's skybright.cal as gensky sets it up (blend at the horizon)."""
    kind, zen, ground = int(params[0]), params[1], params[2]
    dz_c = np.clip(dz, -1, 1)
    if kind in (2, 3):
        sky = zen * (1 + 2 * dz_c) / 3 if kind == 2 else zen * np.ones_like(dz_c)
    else:
        f2, sx, sy, sz = params[3:7]
        cg = np.clip(dx * sx + dy * sy + dz * sz, -1, 1)
        g = np.arccos(cg)
        if kind == 1:
            grad = np.where(dz_c > 0.01, 1 - np.exp(-0.32 / np.maximum(dz_c, 1e-9)), 1.0)
            sky = zen * (0.91 + 10 * np.exp(-3 * g) + 0.45 * cg * cg) * grad / f2
        else:
            zt, eta = math.acos(sz), np.arccos(dz_c)
            sky = (zen * ((1.35 * np.sin(5.631 - 3.59 * eta) + 3.12) * math.sin(4.396 - 2.6 * zt)
                          + 6.37 - eta) / 2.326
                   * np.exp(g * -0.563 * ((2.629 - eta) * (1.562 - zt) + 0.812)) / f2)
    w1, w2 = (dz_c + 1.01) ** 10, (dz_c + 1.01) ** -10
    return (w1 * sky + w2 * ground) / (w1 + w2)


def sphere_grid(n_alt, upper=True):
    """Midpoint directions (Radiance frame) and solid angles over a hemisphere."""
    alt = (np.arange(n_alt) + 0.5) / n_alt * (math.pi / 2)
    n_az = 2 * n_alt
    az = (np.arange(n_az) + 0.5) / n_az * 2 * math.pi
    A, Z = np.meshgrid(alt, az, indexing="ij")
    s = 1.0 if upper else -1.0
    d = np.stack([np.cos(A) * np.sin(Z), np.cos(A) * np.cos(Z), s * np.sin(A)], axis=-1)
    dw = np.cos(A) * (math.pi / 2 / n_alt) * (2 * math.pi / n_az)
    return d.reshape(-1, 3), dw.reshape(-1)


class Sky:
    """The sky as rendered: radiance functions in Radiance's frame (W/sr/m2)."""

    def __init__(self, a):
        self.model, self.cie_type = a.sky, a.cie_type
        self.cie = CIE_GENERAL.get(a.cie_type) if a.sky == "cie_general" else None
        self.eh = a.horizontal_illuminance
        self.rho = a.ground_reflectance
        self.horizon = a.horizon
        self.rot = frame(a.north)
        self.altitude, self.azimuth = a.sun_altitude, a.sun_azimuth
        self.sun_dir_iso = sun_vector(self.altitude, self.azimuth, self.rot)
        self.sun_dir = self.rot @ self.sun_dir_iso
        self.requested_sun = a.sun_normal_illuminance
        if self.model == "cie_general" and self.horizon == "gensky":
            fail("cie_general exists only with --horizon sharp")

    def uses_sun(self):
        return self.model in ("clear", "intermediate") or (self.model == "cie_general" and self.cie_type != 5)

    def gensky_args(self):
        g_az = ((self.azimuth - 180.0 + 180.0) % 360.0) - 180.0  # west of south
        args = ["gensky", "-ang", f"{self.altitude:.10g}", f"{g_az:.10g}"]
        en = self.requested_sun
        flag = {"overcast": ["-c"], "uniform": ["-u"]}.get(self.model)
        if flag is None:
            letter = "i" if self.model == "intermediate" else "s"
            if en is None and self.model == "cie_general":
                en = 0.0
            if en is None:
                flag = ["+" + letter]
            elif en > 0:
                flag = ["+" + letter, "-r", f"{en / LUMENS_PER_WATT / SUN_SOLID_ANGLE:.10g}"]
            else:  # -r 0: without it gensky still lights the ground with its default sun
                flag = ["-" + letter, "-r", "0"]
        return args + flag + ["-B", f"{self.eh / LUMENS_PER_WATT:.10g}",
                              "-g", f"{self.rho:.10g}"]

    def run_gensky(self, run):
        self.gensky_cmd = self.gensky_args()
        out = run(self.gensky_cmd)
        self.gensky_text = out
        m = re.search(r"void light solar\s+0\s+0\s+3\s+(\S+)", out)
        self.solarbr = float(m.group(1)) if m else 0.0
        if m and self.horizon == "sharp" and self.requested_sun:
            # gensky prints 4 digits; the sharp sky writes the sun at full precision.
            self.solarbr = self.requested_sun / LUMENS_PER_WATT / SUN_SOLID_ANGLE
        self.sun_normal_lux = self.solarbr * SUN_SOLID_ANGLE * LUMENS_PER_WATT
        if m:
            d = re.search(r"solar source sun\s+0\s+0\s+4\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)", out)
            gdir = np.array([float(d.group(k)) for k in (1, 2, 3)])
            if np.abs(gdir - self.sun_dir).max() > 2e-5:
                fail(f"gensky's sun {gdir} is not ours {self.sun_dir} (sun above 87 degrees?)")
        m = re.search(r"void brightfunc skyfunc\s+2 skybr skybright.cal\s+0\s+(\d+)((?:\s+\S+)+)", out)
        self.gensky_params = [float(v) for v in m.group(2).split()][: int(m.group(1))]
        if self.model in ("clear", "intermediate", "cie_general") and self.altitude > 87:
            fail("sun altitude above 87 degrees: gensky lowers it")
        sun_h = self.sun_normal_lux * max(self.sun_dir[2], 0.0)
        if self.horizon == "gensky":
            self.ground = self.gensky_params[2]
            self.eh_rendered = self.integrate_horizontal()
        else:
            d, dw = sphere_grid(1200)
            rel = relative_luminance(self.model, d[:, 2], d @ self.sun_dir, self.sun_dir[2], self.cie)
            self.zenith_factor = self.eh / LUMENS_PER_WATT / np.sum(rel * d[:, 2] * dw)
            self.ground = self.rho * (self.eh + sun_h) / math.pi / LUMENS_PER_WATT
            self.eh_rendered = self.integrate_horizontal()
        self.zenith_luminance = float(self.radiance(np.array([[0.0, 0.0, 1.0]]))[0]) * LUMENS_PER_WATT

    def radiance(self, d):
        """Sky or ground radiance, W/sr/m2, for unit directions d (Radiance frame)."""
        d = np.atleast_2d(d)
        if self.horizon == "gensky":
            return gensky_skybright(self.gensky_params, d[:, 0], d[:, 1], d[:, 2])
        rel = relative_luminance(self.model, d[:, 2], d @ self.sun_dir, self.sun_dir[2], self.cie)
        return np.where(d[:, 2] > 0, self.zenith_factor * rel, self.ground)

    def integrate_horizontal(self, n=1200):
        d, dw = sphere_grid(n)
        return float(np.sum(self.radiance(d) * d[:, 2] * dw)) * LUMENS_PER_WATT

    def illuminance_unobstructed(self, normal_iso, n=600):
        """Sky + ground + sun illuminance on an unobstructed plane, lux."""
        nr = self.rot @ np.asarray(normal_iso, float)
        total = 0.0
        for upper in (True, False):
            d, dw = sphere_grid(n, upper)
            total += np.sum(self.radiance(d) * np.maximum(d @ nr, 0) * dw)
        return total * LUMENS_PER_WATT + self.sun_normal_lux * max(nr @ self.sun_dir, 0.0)

    def radiance_text(self):
        glows = ("\nskyfunc glow sky_glow\n0\n0\n4 1 1 1 0\n\nsky_glow source sky\n0\n0\n4 0 0 1 180\n"
                 "\nskyfunc glow ground_glow\n0\n0\n4 1 1 1 0\n\n"
                 "ground_glow source ground\n0\n0\n4 0 0 -1 180\n")
        if self.horizon == "gensky":
            return self.gensky_text + glows
        sun = ""
        m = re.search(r"void light solar.*?(?=\nvoid brightfunc)", self.gensky_text, re.S)
        if m:
            b = f"{self.solarbr:.10g}"
            sun = re.sub(r"(void light solar\s+0\s+0\s+3)\s+\S+\s+\S+\s+\S+",
                         lambda g: f"{g.group(1)} {b} {b} {b}", m.group(0)) + "\n"
        cie = self.cie or (0, 0, 0, 0, 0)
        args = [MODEL_CODE[self.model], self.zenith_factor, self.ground, *self.sun_dir, *cie]
        return (f"# sky: {' '.join(self.gensky_cmd)}, sky function replaced (sharp horizon)\n"
                + sun + "\nvoid brightfunc skyfunc\n2 skybr isorad_sky.cal\n0\n"
                + f"{len(args)} " + " ".join(f"{v:.10g}" for v in args) + "\n" + glows)

    def summary(self):
        s = {"model": self.model, "horizon": self.horizon,
             "horizontal_illuminance_requested_lux": self.eh,
             "horizontal_illuminance_rendered_lux": round(self.eh_rendered, 3),
             "zenith_luminance_cd_m2": round(self.zenith_luminance, 4),
             "ground_reflectance": self.rho,
             "ground_luminance_cd_m2": round(self.ground * LUMENS_PER_WATT, 4),
             "north_isorad": [round(v, 9) + 0.0 for v in self.rot[1]],
             "east_isorad": [round(v, 9) + 0.0 for v in self.rot[0]],
             "gensky": " ".join(self.gensky_cmd)}
        if self.uses_sun() or self.sun_normal_lux > 0:
            s.update({"sun_altitude_deg": self.altitude,
                      "sun_azimuth_deg_clockwise_from_north": self.azimuth,
                      "sun_direction_isorad": [round(v, 6) + 0.0 for v in self.sun_dir_iso],
                      "sun_normal_illuminance_lux": round(self.sun_normal_lux, 3)})
        else:
            s["sun"] = "none (the sky does not depend on the sun's position; -ang is a placeholder)"
        if self.cie:
            s["cie_type"] = self.cie_type
            s["cie_abcde"] = list(self.cie)
        return s


# --------------------------------------------------------------------------
# Scene conversion.

def read_mtl(path):
    mats, cur = {}, None
    with open(path) as f:
        for line in f:
            w = line.split("#", 1)[0].split()
            if not w:
                continue
            if w[0] == "newmtl":
                cur = " ".join(w[1:])
                mats[cur] = {"Kd": (0.0, 0.0, 0.0), "Ke": (0.0, 0.0, 0.0), "Tf": 0.0, "Ks": 0.0}
            elif cur is not None and w[0] in ("Kd", "Ke", "Tf"):
                try:
                    v = [float(x) for x in w[1:4]]
                except ValueError:
                    fail(f"{path}: `{line.strip()}`: give {w[0]} as r g b")
                v = v * 3 if len(v) == 1 else v
                if w[0] == "Tf":  # isorad reads Tf's Rec. 709 luminance as Tn
                    mats[cur]["Tf"] = float(REC709 @ np.array(v))
                else:
                    mats[cur][w[0]] = tuple(v)
    return mats


def read_obj(path):
    verts, faces, mtllibs, mat = [], [], [], None
    with open(path) as f:
        for number, line in enumerate(f, 1):
            w = line.split("#", 1)[0].split()
            if not w:
                continue
            if w[0] == "v":
                verts.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                idx = []
                for t in w[1:]:
                    k = int(t.split("/")[0])
                    idx.append(k - 1 if k > 0 else len(verts) + k)
                faces.append((mat, idx, number))
            elif w[0] == "usemtl":
                mat = " ".join(w[1:])
            elif w[0] == "mtllib":
                mtllibs.append(" ".join(w[1:]))
    return np.array(verts, dtype=float), faces, mtllibs


def radiance_name(name):
    return "m_" + re.sub(r"[^A-Za-z0-9_.-]", "_", name or "default")


def glass_transmissivity(tn):
    return (math.sqrt(0.8402528435 + 0.0072522239 * tn * tn) - 0.9166530661) / 0.0036261119 / tn


def scene_to_radiance(scene_path, rot):
    """The scene's OBJ as Radiance text, and notes on the conversion."""
    with open(scene_path, "rb") as f:
        spec = tomllib.load(f)
    base = os.path.dirname(os.path.abspath(scene_path))
    obj_path = os.path.join(base, spec["obj"])
    verts, faces, mtllibs = read_obj(obj_path)
    mats = {}
    for lib in mtllibs:
        mats.update(read_mtl(os.path.join(os.path.dirname(obj_path), lib)))
    notes, out, used = [], [], set()
    for name, m in mats.items():
        rn = radiance_name(name)
        if m["Tf"] > 0:
            if max(m["Kd"]) > 0:
                notes.append(f"material {name}: Kd ignored on glazing (Radiance glass)")
            t = glass_transmissivity(m["Tf"])
            out.append(f"void glass {rn}\n0\n0\n3 {t:.8g} {t:.8g} {t:.8g}\n")
        elif max(m["Ke"]) > 0:
            if max(m["Kd"]) > 0:
                notes.append(f"material {name}: Kd ignored on an emitter (Radiance light)")
            out.append(f"void light {rn}\n0\n0\n3 {m['Ke'][0]:.8g} {m['Ke'][1]:.8g} {m['Ke'][2]:.8g}\n")
        else:
            kd = m["Kd"]
            out.append(f"void plastic {rn}\n0\n0\n5 {kd[0]:.8g} {kd[1]:.8g} {kd[2]:.8g} 0 0\n")
    rv = verts @ rot.T
    count = 0
    for mat, idx, line in faces:
        if mat not in mats:
            mats[mat] = None
            if radiance_name(mat) not in used:
                notes.append(f"material {mat} undefined: black")
                out.append(f"void plastic {radiance_name(mat)}\n0\n0\n5 0 0 0 0 0\n")
        used.add(radiance_name(mat))
        p = rv[idx]
        normal = np.zeros(3)  # Newell's normal
        for k in range(len(p)):
            a, b = p[k], p[(k + 1) % len(p)]
            normal += np.cross(a, b)
        area = np.linalg.norm(normal) / 2
        if area < 1e-12:
            notes.append(f"{os.path.basename(obj_path)}:{line}: degenerate face skipped")
            continue
        normal /= 2 * area
        size = np.ptp(p, axis=0).max()
        planar = np.abs((p - p[0]) @ normal).max() <= 1e-6 * max(size, 1.0)
        polys = [p] if planar else [np.array([p[0], p[k], p[k + 1]]) for k in range(1, len(p) - 1)]
        for q in polys:
            count += 1
            coords = "\n".join(f"  {x:.9g} {y:.9g} {z:.9g}" for x, y, z in q)
            out.append(f"{radiance_name(mat)} polygon f{count}\n0\n0\n{3 * len(q)}\n{coords}\n")
    return "\n".join(out), notes, count, spec


# --------------------------------------------------------------------------
# Points.

def read_points(path, default_normal):
    """x,y,z[,nx,ny,nz] with a header, or isorad grid's CSV (# normal = ...,
    x,y,z,illuminance_lux,status)."""
    normal, header, rows = None, None, []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if not s:
                continue
            if s.startswith("#"):
                m = re.match(r"#\s*normal\s*=\s*(\S+)\s+(\S+)\s+(\S+)", s)
                if m:
                    normal = [float(m.group(k)) for k in (1, 2, 3)]
                continue
            fields = [t.strip() for t in s.split(",")]
            if header is None and fields[0].lower().startswith("x"):
                header = [t.lower() for t in fields]
                continue
            rows.append(fields)
    if header is None:
        header = ["x", "y", "z", "nx", "ny", "nz"][: len(rows[0])] if rows else []
    col = {name: k for k, name in enumerate(header)}
    if not rows or not all(c in col for c in "xyz"):
        fail(f"{path}: need columns x,y,z")
    pts = np.array([[float(r[col[c]]) for c in "xyz"] for r in rows])
    if all(c in col for c in ("nx", "ny", "nz")):
        nrm = np.array([[float(r[col[c]]) for c in ("nx", "ny", "nz")] for r in rows])
        source = "file"
    else:
        nrm = np.tile(normal if normal is not None else default_normal, (len(rows), 1))
        source = "isorad grid header" if normal is not None else "--normal"
    length = np.linalg.norm(nrm, axis=1)
    if np.any(length == 0):
        fail(f"{path}: a normal is zero")
    nrm /= length[:, None]
    status = [r[col["status"]] for r in rows] if "status" in col else None
    return pts, nrm, status, source


# --------------------------------------------------------------------------
# Radiance.

class Radiance:
    def __init__(self, prefix, workdir):
        self.env = dict(os.environ)
        if prefix:
            self.env["PATH"] = os.path.join(prefix, "bin") + os.pathsep + self.env["PATH"]
            lib = os.path.join(prefix, "lib")
        else:
            exe = shutil.which("rtrace")
            if exe is None:
                fail("rtrace not found: give --radiance PREFIX or put Radiance on PATH")
            lib = os.path.join(os.path.dirname(os.path.dirname(exe)), "lib")
        self.env["RAYPATH"] = os.pathsep.join([".", lib, self.env.get("RAYPATH", "")]).rstrip(os.pathsep)
        self.dir = workdir

    def run(self, args, stdin=None):
        p = subprocess.run(args, input=stdin, capture_output=True, text=True, cwd=self.dir, env=self.env)
        if p.returncode != 0:
            fail(f"{' '.join(args)} failed: {p.stderr.strip()}")
        return p.stdout

    def version(self):
        return self.run(["rtrace", "-version"]).strip()


def rtrace_options(a):
    lw = a.lw if a.lw is not None else 0.01 / a.ad
    return ["-I+", "-h-", "-ab", str(a.ab), "-ad", str(a.ad), "-as", str(a.as_), "-aa", "0",
            "-lr", "-16", "-lw", f"{lw:.3g}", "-dt", "0", "-dc", "1", "-dj", "0", "-st", "0",
            "-u+"] + (a.extra_rtrace.split() if a.extra_rtrace else [])


def trace(rad, octree, opts, pts_r, nrm_r, runs):
    """Irradiance (W/m2, Rec. 709 luminance of RGB) per point and run."""
    results, second = [], None
    for run in range(runs):
        # rtrace -u+ seeds its random numbers with the time in seconds.
        while second is not None and int(time.time()) == second:
            time.sleep(0.05)
        second = int(time.time())
        order = np.arange(len(pts_r)) if run == 0 else np.random.default_rng(run).permutation(len(pts_r))
        lines = "".join(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g} {n[0]:.9g} {n[1]:.9g} {n[2]:.9g}\n"
                        for p, n in zip(pts_r[order], nrm_r[order]))
        out = rad.run(["rtrace", *opts, octree], stdin=lines)
        rgb = np.array([[float(v) for v in line.split()] for line in out.strip().splitlines()])
        if rgb.shape != (len(pts_r), 3):
            fail(f"rtrace gave {rgb.shape} values for {len(pts_r)} points")
        value = np.empty(len(pts_r))
        value[order] = rgb @ REC709
        results.append(value)
    return np.array(results)


# --------------------------------------------------------------------------
# Numerical integral over openings (black rooms).

def parse_opening(text):
    try:
        corners = [np.array([float(v) for v in c.split(",")]) for c in text.split(";")]
        assert len(corners) == 3 and all(len(c) == 3 for c in corners)
    except (ValueError, AssertionError):
        fail(f"--opening {text!r}: give X,Y,Z;X,Y,Z;X,Y,Z (a corner and its two neighbours)")
    return corners


def pane_transmittance(cos_i, tn_normal, n=1.52):
    """Transmittance of a clear pane of normal-incidence transmittance
    tn_normal at incidence cosine cos_i: Fresnel (s and p) at both faces,
    absorption tn^(1/cos_t) per pass, all inter-reflections in the pane."""
    tau0 = glass_transmissivity(tn_normal)
    cos_i = np.clip(cos_i, 1e-9, 1)
    cos_t = np.sqrt(1 - (1 - cos_i**2) / n**2)
    tau = tau0 ** (1 / cos_t)
    total = 0
    for r in (((cos_i - n * cos_t) / (cos_i + n * cos_t)) ** 2,
              ((cos_t - n * cos_i) / (cos_t + n * cos_i)) ** 2):
        total = total + 0.5 * (1 - r) ** 2 * tau / (1 - r * r * tau * tau)
    return total


def opening_integral(sky, pts, nrm, openings, order=48, glass=None):
    """Sky (and sun) illuminance at each point through the openings, lux;
    `glass`: the openings hold a pane of that normal transmittance."""
    x, w = np.polynomial.legendre.leggauss(order)
    u, wu = (x + 1) / 2, w / 2
    total = np.zeros(len(pts))
    for o, c1, c2 in openings:
        e1, e2 = c1 - o, c2 - o
        on = np.cross(e1, e2)
        area = np.linalg.norm(on)
        on /= area
        q = o + u[:, None, None] * e1 + u[None, :, None] * e2  # (n, n, 3)
        wq = (wu[:, None] * wu[None, :]) * area
        for k, (p, n) in enumerate(zip(pts, nrm)):
            v = q - p
            r2 = np.sum(v * v, axis=-1)
            d = v / np.sqrt(r2)[..., None]
            cos_p = np.maximum(d @ n, 0)
            cos_o = np.abs(d @ on)
            lum = sky.radiance((d @ sky.rot.T).reshape(-1, 3)).reshape(r2.shape)
            tr = pane_transmittance(cos_o, glass) if glass else 1.0
            total[k] += np.sum(wq * lum * tr * cos_p * cos_o / r2) * LUMENS_PER_WATT
            s = sky.sun_dir_iso
            if sky.sun_normal_lux > 0 and n @ s > 0 and abs(s @ on) > 1e-12:
                t = ((o - p) @ on) / (s @ on)
                if t > 0:
                    h = p + t * s - o
                    g = np.array([[e1 @ e1, e1 @ e2], [e1 @ e2, e2 @ e2]])
                    a, b = np.linalg.solve(g, [h @ e1, h @ e2])
                    if 0 <= a <= 1 and 0 <= b <= 1:
                        tr = pane_transmittance(abs(s @ on), glass) if glass else 1.0
                        total[k] += sky.sun_normal_lux * (n @ s) * tr
    return total


# --------------------------------------------------------------------------

def statistics(lux, df, counted):
    e, f = lux[counted], df[counted]
    return {"points": int(counted.sum()), "mean_lux": round(float(e.mean()), 3),
            "mean_df_pct": round(float(f.mean()), 4), "median_df_pct": round(float(np.median(f)), 4),
            "min_df_pct": round(float(f.min()), 4), "max_df_pct": round(float(f.max()), 4),
            "uniformity_min_over_mean": round(float(f.min() / f.mean()), 4) if f.mean() > 0 else None}


def resolve_sky(a, spec):
    sky_t, sun_t = spec.get("sky", {}), spec.get("sun", None)
    if a.sky is None:
        model = sky_t.get("model", "cie_overcast")
        if model not in TOML_MODELS:
            fail(f"[sky] model {model!r} unknown")
        a.sky = TOML_MODELS[model]
    if a.cie_type is None:
        a.cie_type = int(sky_t.get("type", 0)) or None
    if a.sky == "cie_general" and a.cie_type not in CIE_GENERAL:
        fail("cie_general needs --cie-type (or [sky] type) 1..15")
    if a.horizontal_illuminance is None:
        a.horizontal_illuminance = float(sky_t.get("horizontal_illuminance", 10000.0))
    if a.ground_reflectance is None:
        a.ground_reflectance = float(sky_t.get("ground_reflectance", 0.2))
    if a.north is None:
        a.north = [float(v) for v in sky_t.get("north", [0.0, 0.0, -1.0])]
    sun_t = sun_t or {}
    if a.sun_altitude is None and "altitude_deg" in sun_t:
        a.sun_altitude = float(sun_t["altitude_deg"])
    if a.sun_azimuth is None and "azimuth_deg" in sun_t:
        a.sun_azimuth = float(sun_t["azimuth_deg"])
    if a.sun_normal_illuminance is None and a.from_toml:
        a.sun_normal_illuminance = float(sun_t.get("normal_illuminance", 0.0))
    needs_sun = a.sky in ("clear", "intermediate") or (a.sky == "cie_general" and a.cie_type != 5)
    if a.sun_altitude is None or a.sun_azimuth is None:
        if needs_sun:
            fail(f"the {a.sky} sky needs the sun's position (--sun-altitude, --sun-azimuth or [sun])")
        a.sun_altitude, a.sun_azimuth = 45.0, 180.0  # unused by the sky


def compute(a):
    with open(a.scene, "rb") as f:
        spec = tomllib.load(f)
    a.from_toml = "sky" in spec or "sun" in spec
    resolve_sky(a, spec)
    sky = Sky(a)
    workdir = tempfile.mkdtemp(prefix="daylight_radiance_")
    try:
        rad = Radiance(a.radiance, workdir)
        sky.run_gensky(rad.run)
        scene_text, notes, polygons, _ = scene_to_radiance(a.scene, sky.rot)
        with open(os.path.join(workdir, "isorad_sky.cal"), "w") as f:
            f.write(SKY_CAL)
        with open(os.path.join(workdir, "sky.rad"), "w") as f:
            f.write(sky.radiance_text())
        with open(os.path.join(workdir, "scene.rad"), "w") as f:
            f.write(scene_text)
        rad.run(["sh", "-c", "oconv sky.rad scene.rad > scene.oct"])
        pts, nrm, status, normal_source = read_points(a.points, a.normal)
        opts = rtrace_options(a)
        irr = trace(rad, "scene.oct", opts, pts @ sky.rot.T, nrm @ sky.rot.T, a.runs)
        if a.keep:
            shutil.copytree(workdir, a.keep, dirs_exist_ok=True)
        version = rad.version()
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    runs = irr * LUMENS_PER_WATT
    lux = runs.mean(axis=0)
    df = 100 * lux / sky.eh_rendered
    pair = np.abs(runs[0] - runs[1]) / np.maximum(lux, 1e-9) if a.runs > 1 else None
    counted = np.array([s is None or not s.startswith(("left_out", "unread")) for s in (status or [None] * len(pts))])
    integral = (opening_integral(sky, pts, nrm, [parse_opening(o) for o in a.opening], glass=a.opening_glass)
                if a.opening else None)

    header = ["x", "y", "z", "nx", "ny", "nz", "illuminance_lux", "daylight_factor_pct"]
    header += [f"run{k + 1}_lux" for k in range(a.runs)]
    if pair is not None:
        header.append("runs_rel_diff")
    if status is not None:
        header.append("status")
    if integral is not None:
        header += ["opening_integral_lux", "radiance_over_integral_minus_1"]
    with open(a.out, "w") as f:
        f.write(",".join(header) + "\n")
        for k in range(len(pts)):
            row = [*(f"{v:.4f}" for v in pts[k]), *(f"{v:.6f}" for v in nrm[k]),
                   f"{lux[k]:.3f}", f"{df[k]:.5f}", *(f"{runs[r][k]:.3f}" for r in range(a.runs))]
            if pair is not None:
                row.append(f"{pair[k]:.5f}")
            if status is not None:
                row.append(status[k])
            if integral is not None:
                row += [f"{integral[k]:.3f}", f"{lux[k] / integral[k] - 1:.5f}" if integral[k] > 0 else ""]
            f.write(",".join(row) + "\n")

    summary = {
        "scene": a.scene, "points_file": a.points, "normals_from": normal_source,
        "radiance": version, "rtrace": "rtrace " + " ".join(opts),
        "runs": a.runs, "polygons": polygons, "conversion_notes": notes,
        "sky": sky.summary(), "statistics": statistics(lux, df, counted),
    }
    if pair is not None:
        c = pair[counted & (lux > 0)]
        summary["noise"] = {
            "mean_abs_rel_diff_between_runs": round(float(c.mean()), 5),
            "max_abs_rel_diff_between_runs": round(float(c.max()), 5),
            "mean_of_two_runs_rel_std_error_est": round(float(c.mean() * math.sqrt(math.pi / 8)), 5),
            "mean_illuminance_rel_diff_between_runs": round(
                float(abs(runs[0][counted].mean() - runs[1][counted].mean()) / lux[counted].mean()), 6),
        }
    if integral is not None:
        rel = lux[counted] / integral[counted] - 1
        summary["opening_integral"] = {
            "openings": a.opening, "pane_normal_transmittance": a.opening_glass,
            "mean_rel_diff_radiance_minus_integral": round(float(rel.mean()), 5),
            "mean_abs_rel_diff": round(float(np.abs(rel).mean()), 5),
            "max_abs_rel_diff": round(float(np.abs(rel).max()), 5),
            "mean_illuminance_ratio": round(float(lux[counted].mean() / integral[counted].mean()), 5),
        }
    text = json.dumps(summary, indent=2)
    if a.json:
        with open(a.json, "w") as f:
            f.write(text + "\n")
    print(text)


# --------------------------------------------------------------------------
# Self-test: unobstructed points, against analytic and numerical integrals.

def self_test(a):
    workdir = tempfile.mkdtemp(prefix="daylight_radiance_test_")
    failures = []
    try:
        rad = Radiance(a.radiance, workdir)
        with open(os.path.join(workdir, "isorad_sky.cal"), "w") as f:
            f.write(SKY_CAL)
        opts = rtrace_options(a)

        def measure(args, normals):
            sky = Sky(args)
            sky.run_gensky(rad.run)
            with open(os.path.join(workdir, "sky.rad"), "w") as f:
                f.write(sky.radiance_text())
            rad.run(["sh", "-c", "oconv sky.rad > sky.oct"])
            nrm = np.array(normals, float)
            pts = np.zeros_like(nrm)
            irr = trace(rad, "sky.oct", opts, pts, nrm @ sky.rot.T, 1)[0] * LUMENS_PER_WATT
            return sky, irr

        def check(label, got, want, tol):
            err = got / want - 1
            ok = abs(err) <= tol
            print(f"  {'ok  ' if ok else 'FAIL'} {label}: {got:.2f} lx, expected {want:.2f} lx "
                  f"({100 * err:+.3f} %, tolerance {100 * tol:.1f} %)")
            if not ok:
                failures.append(label)

        def args(**kw):
            base = dict(sky="overcast", cie_type=None, horizontal_illuminance=10000.0,
                        ground_reflectance=0.2, north=[0.0, 0.0, -1.0], sun_altitude=45.0,
                        sun_azimuth=180.0, sun_normal_illuminance=None, horizon="sharp")
            base.update(kw)
            return argparse.Namespace(**base)

        eh, rho = 10000.0, 0.2
        east, north, west, south, up = [1, 0, 0], [0, 0, -1], [-1, 0, 0], [0, 0, 1], [0, 1, 0]
        # Moon-Spencer (CIE overcast) sky L = Lz (1 + 2 sin a)/3: E_h = 7 pi Lz / 9;
        # a vertical plane sees half the sky, 2 Lz/3 int_0^{pi/2} (1 + 2 sin a) cos^2 a da
        # = Lz (pi/6 + 4/9), and half the uniform ground L_g = rho E_h / pi, i.e.
        # E_v = E_h (3/14 + 4/(7 pi) + rho/2).
        ev = eh * (3 / 14 + 4 / (7 * math.pi) + rho / 2)
        print(f"overcast sky, E_h = {eh:g} lx, rho_g = {rho}: E_v = E_h (3/14 + 4/(7 pi) + rho/2) = {ev:.2f} lx")
        sky, e = measure(args(), [up, east, north, west, south])
        check("horizontal, overcast", e[0], eh, 0.005)
        for label, v in zip(("east", "north", "west", "south"), e[1:]):
            check(f"vertical facing {label}, overcast", v, ev, 0.01)
        print("gensky's own overcast skyfunc (horizon blend), against the same analytic values:")
        sky, e = measure(args(horizon="gensky"), [up, south])
        check("horizontal, overcast, gensky skyfunc", e[0], eh, 0.005)
        check("vertical, overcast, gensky skyfunc", e[1], ev, 0.01)
        check("vertical, overcast, gensky skyfunc vs its numerical integral", e[1],
              sky.illuminance_unobstructed(south), 0.01)
        print("uniform sky: E_v = E_h (1/2 + rho/2)")
        sky, e = measure(args(sky="uniform"), [up, east])
        check("horizontal, uniform", e[0], eh, 0.005)
        check("vertical, uniform", e[1], eh * (0.5 + rho / 2), 0.01)
        print("clear sky with a 70 klx sun at altitude 40, azimuth 90 (east), against numerical integrals:")
        kw = dict(sky="clear", sun_altitude=40.0, sun_azimuth=90.0, sun_normal_illuminance=70000.0)
        sky, e = measure(args(**kw), [up, east, west, south, north])
        sun_h = 70000.0 * math.sin(math.radians(40))
        check("horizontal, clear + sun (= E_h + E_n sin 40)", e[0], eh + sun_h, 0.005)
        for label, n, v in zip(("east", "west", "south", "north"), (east, west, south, north), e[1:]):
            check(f"vertical facing {label}, clear + sun", v, sky.illuminance_unobstructed(n), 0.01)
        print("the same sky with north = +x (east is then +z): the sun lights a plane facing +z")
        sky, e = measure(args(north=[1.0, 0.0, 0.0], **kw), [[0, 0, 1], [0, 0, -1]])
        check("facing +z, north = +x", e[0], sky.illuminance_unobstructed([0, 0, 1]), 0.01)
        check("facing -z, north = +x", e[1], sky.illuminance_unobstructed([0, 0, -1]), 0.01)
        if not e[0] > e[1] + 0.5 * 70000 * math.cos(math.radians(40)):
            failures.append("sun side with north = +x")
        print("intermediate sky, sun at altitude 30, azimuth 200, no beam:")
        sky, e = measure(args(sky="intermediate", sun_altitude=30.0, sun_azimuth=200.0,
                              sun_normal_illuminance=0.0), [up, south, north])
        check("horizontal, intermediate", e[0], eh, 0.005)
        check("vertical facing south, intermediate", e[1], sky.illuminance_unobstructed(south), 0.01)
        check("vertical facing north, intermediate", e[2], sky.illuminance_unobstructed(north), 0.01)
        print("CIE general type 12 (= the CIE clear sky) and type 5 (= uniform):")
        clear, e12 = measure(args(sky="clear", sun_altitude=40.0, sun_azimuth=150.0,
                                  sun_normal_illuminance=0.0), [south])
        sky, e = measure(args(sky="cie_general", cie_type=12, sun_altitude=40.0, sun_azimuth=150.0),
                         [up, south])
        check("horizontal, CIE type 12", e[0], eh, 0.005)
        check("vertical facing south, CIE type 12 vs clear", e[1], e12[0], 0.01)
        sky, e = measure(args(sky="cie_general", cie_type=5), [east])
        check("vertical, CIE type 5 vs uniform", e[0], eh * (0.5 + rho / 2), 0.01)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    print(f"rtrace {' '.join(opts)}")
    if failures:
        fail(f"self-test failed: {', '.join(failures)}")
    print("self-test passed")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", nargs="?", help="isorad scene TOML")
    p.add_argument("--points", help="CSV: x,y,z,nx,ny,nz with a header, or isorad grid's CSV")
    p.add_argument("--out", help="CSV to write")
    p.add_argument("--json", help="JSON summary to write (also printed)")
    p.add_argument("--sky", choices=sorted(MODEL_CODE))
    p.add_argument("--cie-type", type=int, help="CIE general sky type 1..15")
    p.add_argument("--horizontal-illuminance", type=float, help="lux, sky alone (10000)")
    p.add_argument("--sun-altitude", type=float)
    p.add_argument("--sun-azimuth", type=float, help="degrees clockwise from north")
    p.add_argument("--sun-normal-illuminance", type=float, help="lux; 0 = no sun")
    p.add_argument("--ground-reflectance", type=float, help="(0.2)")
    p.add_argument("--north", type=lambda s: [float(v) for v in s.split(",")], help="(0,0,-1)")
    p.add_argument("--normal", type=lambda s: [float(v) for v in s.split(",")], default=[0.0, 1.0, 0.0],
                   help="normal of points given without one (0,1,0)")
    p.add_argument("--horizon", choices=("sharp", "gensky"), default="sharp")
    p.add_argument("--opening", action="append", default=[], help="X,Y,Z;X,Y,Z;X,Y,Z")
    p.add_argument("--opening-glass", type=float, metavar="TN",
                   help="the openings are glazed: a pane of normal transmittance TN")
    p.add_argument("--ab", type=int, default=12)
    p.add_argument("--ad", type=int, default=8192)
    p.add_argument("--as", dest="as_", type=int, default=0,
                   help="ambient super-samples (0: they bias the result low, see above)")
    p.add_argument("--lw", type=float, help="rtrace -lw (0.01 / ad)")
    p.add_argument("--extra-rtrace", help="more rtrace options, e.g. '-n 2'")
    p.add_argument("--runs", type=int, default=2)
    p.add_argument("--radiance", default=os.environ.get("RADIANCE_PREFIX"),
                   help="Radiance install prefix (bin/, lib/); else PATH")
    p.add_argument("--keep", help="copy the Radiance files (octree, .rad) to this directory")
    p.add_argument("--self-test", action="store_true")
    a = p.parse_args()
    if a.self_test:
        if a.ad == 8192:
            a.ad = 16384
        a.ab = 1
        self_test(a)
        return
    if not (a.scene and a.points and a.out):
        p.error("SCENE, --points and --out are needed (or --self-test)")
    compute(a)


if __name__ == "__main__":
    main()
