#!/usr/bin/env python3
"""Writes urdf/humanoid.urdf: the heavy-limbed humanoid ballast controls (modelled on Orca I).

24 actuated joints: per leg hip yaw/roll/pitch, knee, ankle pitch/roll; per arm shoulder
pitch/roll/yaw, elbow, wrist yaw/pitch. Waist and head are fixed into the torso. Every link is a
solid box for its inertia, so each inertia is physically valid by construction; masses are set
so the limbs carry about 64 % of the total, as on the paper's robot. Run it after editing the
tables below: python3 urdf/generate_humanoid.py > urdf/humanoid.urdf

Tests make variants of it with options (a vendor's URDF, say, has no links at the toes, heels,
IMU and lidar: --no-frame-links, and the profile places those frames on the feet, the pelvis and
the head).
"""

import argparse
import builtins
import functools
import sys

LEFT, RIGHT = 1, -1

# name: (mass kg, com xyz in link frame, box size xyz for the inertia and collision)
TRUNK = {
    "pelvis": (7.0, (0.0, 0.0, 0.02), (0.16, 0.28, 0.12)),
    "torso": (13.0, (0.0, 0.0, 0.18), (0.20, 0.32, 0.36)),
    "head": (2.5, (0.0, 0.0, 0.10), (0.16, 0.16, 0.20)),
}
LEG = [  # joint, axis, origin in parent, limits (lower, upper) for the left side, effort, velocity, link
    ("hip_yaw", "0 0 1", (0.0, 0.10, -0.06), (-0.6, 0.9), 90, 12,
     ("hip_yaw_link", 1.5, (0.0, 0.0, -0.03), (0.08, 0.08, 0.08))),
    ("hip_roll", "1 0 0", (0.0, 0.0, -0.07), (-0.35, 0.7), 150, 12,
     ("hip_roll_link", 2.0, (0.0, 0.0, 0.0), (0.10, 0.10, 0.10))),
    ("hip_pitch", "0 1 0", (0.0, 0.0, 0.0), (-2.2, 0.9), 250, 14,
     ("thigh", 4.5, (0.0, 0.0, -0.16), (0.10, 0.10, 0.38))),
    ("knee", "0 1 0", (0.0, 0.0, -0.38), (0.0, 2.4), 250, 14,
     ("shin", 3.0, (0.0, 0.0, -0.16), (0.08, 0.08, 0.38))),
    ("ankle_pitch", "0 1 0", (0.0, 0.0, -0.38), (-1.0, 0.8), 120, 12,
     ("ankle_link", 0.5, (0.0, 0.0, 0.0), (0.05, 0.05, 0.05))),
    ("ankle_roll", "1 0 0", (0.0, 0.0, 0.0), (-0.45, 0.45), 60, 12,
     ("foot", 1.5, (0.03, 0.0, -0.045), (0.24, 0.10, 0.03))),
]
ARM = [
    ("shoulder_pitch", "0 1 0", (0.0, 0.20, 0.30), (-3.1, 2.0), 80, 12,
     ("shoulder_pitch_link", 1.2, (0.0, 0.03, 0.0), (0.08, 0.08, 0.08))),
    ("shoulder_roll", "1 0 0", (0.0, 0.06, 0.0), (-0.3, 2.8), 80, 12,
     ("shoulder_roll_link", 1.0, (0.0, 0.0, -0.04), (0.08, 0.08, 0.08))),
    ("shoulder_yaw", "0 0 1", (0.0, 0.0, -0.10), (-2.0, 2.0), 40, 12,
     ("upper_arm", 1.8, (0.0, 0.0, -0.08), (0.08, 0.08, 0.20))),
    ("elbow", "0 1 0", (0.0, 0.0, -0.18), (-2.5, 0.1), 60, 12,
     ("forearm", 1.4, (0.0, 0.0, -0.10), (0.07, 0.07, 0.22))),
    ("wrist_yaw", "0 0 1", (0.0, 0.0, -0.22), (-2.0, 2.0), 15, 15,
     ("wrist_link", 0.6, (0.0, 0.0, -0.02), (0.06, 0.06, 0.05))),
    ("wrist_pitch", "0 1 0", (0.0, 0.0, -0.04), (-1.2, 1.2), 15, 15,
     ("hand", 0.75, (0.0, 0.0, -0.07), (0.04, 0.09, 0.14))),
]
# Joints mirrored by the sagittal plane swap and negate their limits on the right side.
MIRRORED = {"hip_yaw", "hip_roll", "shoulder_roll", "shoulder_yaw", "wrist_yaw"}
SOLE_Z = -0.06
CONTACTS = {"toe": (0.13, 0.0, SOLE_Z), "heel": (-0.07, 0.0, SOLE_Z)}


def f(x):
    return "%g" % x


def xyz(v):
    return " ".join(f(c) for c in v)


def box_inertia(m, size):
    x, y, z = size
    return (m / 12 * (y * y + z * z), m / 12 * (x * x + z * z), m / 12 * (x * x + y * y))


POINT_FEET = False


def collision(name, com, size):
    if POINT_FEET and name.endswith("_foot"):
        return """    <collision>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <geometry><sphere radius="0.002"/></geometry>
    </collision>
"""
    return f"""    <collision>
      <origin xyz="{xyz(com)}" rpy="0 0 0"/>
      <geometry><box size="{xyz(size)}"/></geometry>
    </collision>
"""


def link(name, mass, com, size):
    ixx, iyy, izz = box_inertia(mass, size)
    return f"""  <link name="{name}">
    <inertial>
      <origin xyz="{xyz(com)}" rpy="0 0 0"/>
      <mass value="{f(mass)}"/>
      <inertia ixx="{ixx:.6g}" ixy="0" ixz="0" iyy="{iyy:.6g}" iyz="0" izz="{izz:.6g}"/>
    </inertial>
{collision(name, com, size)}  </link>
"""


def frame_link(name):
    return f'  <link name="{name}"/>\n'


def fixed(name, parent, child, origin):
    return f"""  <joint name="{name}" type="fixed">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="{xyz(origin)}" rpy="0 0 0"/>
  </joint>
"""


def revolute(name, parent, child, origin, axis, lim, effort, velocity):
    return f"""  <joint name="{name}" type="revolute">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="{xyz(origin)}" rpy="0 0 0"/>
    <axis xyz="{axis}"/>
    <limit lower="{f(lim[0])}" upper="{f(lim[1])}" effort="{f(effort)}" velocity="{f(velocity)}"/>
  </joint>
"""


def chain(side, root, spec):
    prefix = "left_" if side == LEFT else "right_"
    out, parent, masses = [], root, []
    for joint, axis, origin, lim, effort, velocity, (lname, mass, com, size) in spec:
        origin = (origin[0], side * origin[1], origin[2])
        com = (com[0], side * com[1], com[2])
        if side == RIGHT and joint in MIRRORED:
            lim = (-lim[1], -lim[0])
        child = prefix + lname
        out.append(link(child, mass, com, size))
        out.append(revolute(prefix + joint, parent, child, origin, axis, lim, effort, velocity))
        masses.append((child, mass))
        parent = child
    return out, parent, masses


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--no-frame-links", action="store_true",
                    help="no toe, heel, imu and lidar links (as a vendor's URDF): the profile "
                         "places those frames on the feet, pelvis and head")
    ap.add_argument("--point-feet", action="store_true",
                    help="feet whose only collision geometry is a sphere of 2 mm at the link "
                         "origin (no sole box): the simulation stands on the contact points")
    ap.add_argument("-o", "--output", help="write here instead of standard output")
    args = ap.parse_args()
    frames = not args.no_frame_links
    global POINT_FEET
    POINT_FEET = args.point_feet
    parts, table = [], []
    for name, (mass, com, size) in TRUNK.items():
        parts.append(link(name, mass, com, size))
        table.append((name, mass, "trunk"))
    parts.append(fixed("waist", "pelvis", "torso", (0.0, 0.0, 0.10)))
    parts.append(fixed("neck", "torso", "head", (0.0, 0.0, 0.45)))
    if frames:
        parts.append(frame_link("imu"))
        parts.append(fixed("imu_mount", "pelvis", "imu", (0.0, 0.0, 0.04)))
        parts.append(frame_link("lidar"))
        parts.append(fixed("lidar_mount", "head", "lidar", (0.08, 0.0, 0.10)))
    for side in (LEFT, RIGHT):
        out, foot, masses = chain(side, "pelvis", LEG)
        parts += out
        table += [(n, m, "leg") for n, m in masses]
        prefix = "left_" if side == LEFT else "right_"
        for contact, pos in CONTACTS.items() if frames else ():
            parts.append(frame_link(prefix + contact))
            parts.append(fixed(prefix + contact + "_mount", foot, prefix + contact, pos))
    for side in (LEFT, RIGHT):
        out, _, masses = chain(side, "torso", ARM)
        parts += out
        table += [(n, m, "arm") for n, m in masses]

    total = sum(m for _, m, _ in table)
    limbs = sum(m for _, m, g in table if g != "trunk")
    lines = ["  Link masses (kg):"]
    lines += [f"    {n:<28} {m:6.2f}  {g}" for n, m, g in table]
    lines += [f"    {'total':<28} {total:6.2f}",
              f"    {'limbs (legs + arms)':<28} {limbs:6.2f}  ({100 * limbs / total:.1f} % of total)"]
    out = open(args.output, "w") if args.output else sys.stdout
    print = functools.partial(builtins.print, file=out)
    print('<?xml version="1.0"?>')
    print("<!-- Generated by urdf/generate_humanoid.py: edit the generator, not this file.")
    print("  A human-sized humanoid with heavy limbs, modelled on the paper's Orca I.")
    print("  Base: pelvis (floating). Contact points: left/right toe and heel on the soles.")
    print("\n".join(lines))
    print("-->")
    print('<robot name="ballast_humanoid">')
    print("".join(parts), end="")
    print("</robot>")


if __name__ == "__main__":
    main()
