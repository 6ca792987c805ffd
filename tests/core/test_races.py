"""The vector passes of the right-hand side (rvcore.dynamics.races) hold, for every ball, what the
contact laws of rvcore.contact.laws give that ball taken alone, bit for bit.

The test recomputes each contact ball by ball from the state, with the laws called one at
a time from Python (the way the ball loop of the right-hand side computed them before the
passes), and compares with the scratch the right-hand side left behind. A four-point row
(four arcs, inner and outer) of an imperfect bearing (ISO 492 class Normal: offset
raceways and balls of several sizes) in a running state covers every branch of the laws:
open and closed contacts, a ball off its inner race, pockets touched and not.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pipeline.schema import load_bearing, load_profile
from pipeline.schema.shipped import shipped_file
from rvcore.contact import laws as contact
from rvcore.dynamics import races
from rvcore.simulation.run import run_case
from rvcore.bearing.imperfections import Imperfections, realize
from rvcore.dynamics.rhs import new_diagnostics, rhs
from rvcore.bearing.layout import (A_K, A_RING, BALL_STATES, MAX_ROW_ARCS, MAX_ROW_BALLS, P_DAMP_C, P_DAMP_D, P_DAMPING, P_LAW,
                          P_POCKET_C, R_ARC0, R_BALL0, R_CAGE0, R_CAGE_RI, R_CAGE_RO, R_GUIDE, R_HALF_D, R_NARC,
                          R_PITCH_R, R_POCKET0, R_POCKET_K, R_POCKET_R, R_Z, R_ZROW, compile_bearing)
from rvcore.bearing.laws import FRICTION_LAW_SIZE
from rvcore.profile import CH_SPEED, OperatingPoint, channel_value
from rvcore.dynamics.raceway import ball_offsets, spin_of
from rvcore.contact.pose import ring_angular_velocity, ring_rotation, ring_to_global, to_ring_frame
from rvcore.simulation.settings import SolverSettings

SEED = 3


@pytest.fixture(scope="module")
def running_four_point():
    """The four-point example bearing, class Normal, 60 ms into the short cycle at
    300 °/s: ``(model, y, t, table, meta, diag)`` after one right-hand side."""
    bearing = load_bearing(shipped_file("bearings/four-point-example.toml"))
    rows = tuple(dataclasses.replace(r, imperfections=Imperfections(tolerance_class="normal")) for r in bearing.rows)
    bearing = dataclasses.replace(bearing, rows=rows)
    profile = load_profile(shipped_file("profiles/short.toml"))
    op = OperatingPoint(math.radians(300.0), 8e3, 3e3)
    t = 0.06
    y = run_case(bearing, profile, op, SolverSettings(seed=SEED, end_time=t)).final_state
    model = compile_bearing(realize(bearing, SEED))
    table, meta = profile.resolve(op).arrays()
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    rhs(t, y, np.zeros_like(y), model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)
    return model, y, t, table, meta, diag


def _scratch(diag):
    return diag[diag.size - races.SCRATCH_SIZE:]


def test_the_arc_passes_hold_each_ball_s_race_contacts_bit_for_bit(running_four_point):
    model, y, t, table, meta, diag = running_four_point
    buf, p, row = _scratch(diag), model.params, model.rows[0]
    assert row[R_NARC] == 4
    law = p[P_LAW:P_LAW + FRICTION_LAW_SIZE]
    xi, yi, zi, tx, ty, vxi, vyi, vzi, wxi, wyi = y[:10]
    r = ring_rotation(tx, ty)
    om = ring_angular_velocity(channel_value(table, meta, CH_SPEED, t), wxi, wyi, r[0], r[6], r[2], r[5], r[8])
    cos_spin, sin_spin = spin_of(model.rows, table, meta, t)
    h, zrow, a0 = row[R_HALF_D], row[R_ZROW], int(row[R_ARC0])
    closed = 0
    for j in range(int(row[R_Z])):
        b = int(row[R_BALL0]) + BALL_STATES * j
        px, py, pz, vx, vy, vz, wx, wy, wz = y[b:b + 9]
        rho_b = math.sqrt(px * px + py * py)
        inv_rho_b = 1.0 / rho_b
        plx, ply, plz, rho_l = to_ring_frame(px, py, pz, xi, yi, zi, *r, zrow)
        inv_rho_l = 1.0 / rho_l
        offsets = ball_offsets(model.rows, 0, model.pockets, int(row[R_POCKET0]) + j, plx, ply, inv_rho_l,
                               cos_spin, sin_spin, px * inv_rho_b, py * inv_rho_b)
        for a in range(a0, a0 + 4):
            inner, delta, nlx, nly, nlz = contact.race_arc_penetration(
                model.arcs, a, plx, ply, plz, rho_l, inv_rho_l, px, py, pz - zrow, rho_b, inv_rho_b, h, *offsets)
            assert inner == (model.arcs[a, A_RING] == 0.0)
            o = races.arc(a - a0) + j
            assert buf[o + races.C_DELTA * races.W] == delta
            if delta <= 0.0:
                continue       # the ball loop reads nothing else of an open contact
            closed += 1
            nx, ny, nz = ring_to_global(nlx, nly, nlz, *r) if inner else (nlx, nly, nlz)
            ax, ay, az = h * nx, h * ny, h * nz
            ux, uy, uz = vx + wy * az - wz * ay, vy + wz * ax - wx * az, vz + wx * ay - wy * ax
            if inner:
                qx, qy, qz = px + ax - xi, py + ay - yi, pz + az - zi
                ux -= vxi + om[1] * qz - om[2] * qy
                uy -= vyi + om[2] * qx - om[0] * qz
                uz -= vzi + om[0] * qy - om[1] * qx
            un = ux * nx + uy * ny + uz * nz
            q = contact.normal_force(delta, un, model.arcs[a, A_K], p[P_DAMP_C] * p[P_DAMPING], 1.0 / p[P_DAMP_D])
            force = contact.ball_contact_force(q, nx, ny, nz, ux, uy, uz, nx, ny, nz, ax, ay, az,
                                               *contact.NO_FILM_CONSTANTS, law, contact.friction_kind(law))
            expected = (nlx, nly, nlz, nx, ny, nz, ux, uy, uz, un, q) + tuple(force)
            fields = (races.C_NLX, races.C_NLY, races.C_NLZ, races.C_NX, races.C_NY, races.C_NZ, races.C_UX,
                      races.C_UY, races.C_UZ, races.C_UN, races.C_Q, races.C_FX, races.C_FY, races.C_FZ,
                      races.C_MX, races.C_MY, races.C_MZ)
            got = tuple(buf[o + f * races.W] for f in fields)
            assert got == expected, (j, a)
    assert 0 < closed < 4 * int(row[R_Z])     # some contacts closed, some open


def test_the_pocket_pass_holds_each_ball_s_pocket_contact_bit_for_bit(running_four_point):
    model, y, t, table, meta, diag = running_four_point
    buf, p, row = _scratch(diag), model.params, model.rows[0]
    law = p[P_LAW:P_LAW + FRICTION_LAW_SIZE]
    c0, h = int(row[R_CAGE0]), row[R_HALF_D]
    xc, yc, zc, phi, vxc, vyc, vzc, wc = y[c0:c0 + 8]
    cphi, sphi = math.cos(phi), math.sin(phi)
    touching = 0
    for j in range(int(row[R_Z])):
        b = int(row[R_BALL0]) + BALL_STATES * j
        px, py, pz, vx, vy, vz, wx, wy, wz = y[b:b + 9]
        cs0, sn0 = model.pockets[int(row[R_POCKET0]) + j, :2]
        cth, sth = cphi * cs0 - sphi * sn0, sphi * cs0 + cphi * sn0
        delta, ax, ay, az, a_sec = contact.cage_pocket_penetration(
            row[R_GUIDE], px - xc, py - yc, pz - zc - row[R_ZROW], cth, sth, row[R_PITCH_R], row[R_POCKET_R], h,
            row[R_CAGE_RI], row[R_CAGE_RO])
        o = races.POCKET + j
        assert buf[o + races.P_DELTA * races.W] == delta
        if delta <= 0.0:
            continue
        touching += 1
        dgx, dgy, dgz = ax / a_sec, ay / a_sec, az / a_sec
        ux = vx + wy * az - wz * ay - (vxc - wc * (py + ay - yc))
        uy = vy + wz * ax - wx * az - (vyc + wc * (px + ax - xc))
        uz = vz + wx * ay - wy * ax - vzc
        un = ux * dgx + uy * dgy + uz * dgz
        qp = contact.normal_force(delta, un, row[R_POCKET_K], p[P_POCKET_C] * p[P_DAMPING], 1.0 / p[P_DAMP_D])
        inv_h = 1.0 / h
        force = contact.ball_contact_force(qp, dgx, dgy, dgz, ux, uy, uz, ax * inv_h, ay * inv_h, az * inv_h,
                                           ax, ay, az, *contact.NO_FILM_CONSTANTS, law, contact.friction_kind(law))
        q_hertz = contact.hertz_load(row[R_POCKET_K], delta)
        expected = (ax, ay, az, dgx, dgy, dgz, ux, uy, uz, un, qp, q_hertz) + tuple(force)
        fields = (races.P_AX, races.P_AY, races.P_AZ, races.P_DGX, races.P_DGY, races.P_DGZ, races.P_UX, races.P_UY,
                  races.P_UZ, races.P_UN, races.P_Q, races.P_QH, races.P_FX, races.P_FY, races.P_FZ, races.P_MX,
                  races.P_MY, races.P_MZ)
        assert tuple(buf[o + f * races.W] for f in fields) == expected, j
    assert touching > 0


def test_a_row_beyond_the_scratch_is_refused():
    bearing = load_bearing(shipped_file("bearings/four-point-example.toml"))
    many = dataclasses.replace(bearing, rows=(dataclasses.replace(bearing.rows[0], ball_count=MAX_ROW_BALLS + 1),))
    with pytest.raises(ValueError, match=f"at most {MAX_ROW_BALLS}"):
        compile_bearing(many)
    arcs = bearing.rows[0].inner_arcs
    five = dataclasses.replace(bearing, rows=(dataclasses.replace(bearing.rows[0], inner_arcs=arcs + arcs[:1]),))
    with pytest.raises(ValueError, match=f"at most {MAX_ROW_ARCS}"):
        compile_bearing(five)
