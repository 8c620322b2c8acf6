#!/usr/bin/env python3
"""Writes urdf/humanoid.urdf: the heavy-limbed humanoid ballast controls (modelled on Orca I).

24 actuated joints: per leg hip yaw/roll/pitch, knee, ankle pitch/roll; per arm shoulder
pitch/roll/yaw, elbow, wrist yaw/pitch. Waist and head are fixed into the torso. Every link is a
solid box for its inertia, so each inertia is physically valid by construction; masses are set
so the limbs carry about 64 % of the total, as on the paper's robot. Run it after editing the
tables below: python3 urdf/generate_humanoid.py > urdf/humanoid.urdf

Tests make variants of it with options (a vendor's URDF, say, has no links at the toes, heels,
IMU and lidar: --no-frame-links, and the profile places those frames on the feet, the pelvis and
the head), other robots (hips in another order, 5-joint legs, a 3-joint waist, 7-joint arms,
another total mass), and the quirks of vendors' files (--vendor-quirks).
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
# A 3-joint waist between pelvis and torso (--waist-dof 3): yaw, roll, pitch at the waist joint.
WAIST = [
    ("waist_yaw", "0 0 1", (0.0, 0.0, 0.10), (-1.0, 1.0), 120, 10,
     ("waist_yaw_link", 1.0, (0.0, 0.0, 0.0), (0.08, 0.08, 0.04))),
    ("waist_roll", "1 0 0", (0.0, 0.0, 0.0), (-0.4, 0.4), 120, 10,
     ("waist_roll_link", 1.0, (0.0, 0.0, 0.0), (0.08, 0.08, 0.04))),
]
WAIST_PITCH = ("waist_pitch", "0 1 0", (0.0, 0.0, 0.0), (-0.5, 0.8), 120, 10)
# The seventh arm joint (--arm-dof 7): a wrist roll below the wrist pitch, the hand on it.
WRIST_ROLL = ("wrist_roll", "1 0 0", (0.0, 0.0, -0.04), (-1.0, 1.0), 10, 15,
              ("wrist_pitch_link", 0.3, (0.0, 0.0, -0.02), (0.04, 0.04, 0.04)))
# Joints mirrored by the sagittal plane swap and negate their limits on the right side.
MIRRORED = {"hip_yaw", "hip_roll", "shoulder_roll", "shoulder_yaw", "wrist_yaw", "wrist_roll"}
AXES = {"yaw": "0 0 1", "roll": "1 0 0", "pitch": "0 1 0"}
FINGER_MASS = 0.05  # kg, each hand's finger (--vendor-quirks)
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
QUIRKS = False


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


def visual(name):
    if not QUIRKS:
        return ""
    return f"""    <visual>
      <geometry><mesh filename="package://ballast_description/meshes/{name}.STL"/></geometry>
    </visual>
"""


def link(name, mass, com, size):
    ixx, iyy, izz = box_inertia(mass, size)
    return f"""  <link name="{name}">
{visual(name)}    <inertial>
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


def revolute(name, parent, child, origin, axis, lim, effort, velocity, mimic=None):
    mimic = f'    <mimic joint="{mimic[0]}" multiplier="{f(mimic[1])}" offset="{f(mimic[2])}"/>\n' \
        if mimic else ""
    return f"""  <joint name="{name}" type="revolute">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="{xyz(origin)}" rpy="0 0 0"/>
    <axis xyz="{axis}"/>
    <limit lower="{f(lim[0])}" upper="{f(lim[1])}" effort="{f(effort)}" velocity="{f(velocity)}"/>
{mimic}  </joint>
"""


def leg_spec(hips, ankles, dof):
    """The leg chain with its hip joints in the order `hips` (e.g. pitch-roll-yaw: pitch nearest
    the pelvis), its ankle joints in the order `ankles`, and 5 joints (no hip yaw) or 6. The
    links keep their places (masses, lengths): the first hip links are named by their joint."""
    hip = {j[0]: j for j in LEG[:3]}
    ankle = {j[0]: j for j in LEG[4:]}
    spec, carried = [], None  # a dropped joint's offset and link mass go to the next joint
    for k, axis in enumerate(hips.split("-")):
        name, _, _, lim, effort, velocity, _ = hip["hip_" + axis]
        _, _, origin, _, _, _, (lname, mass, com, size) = LEG[k]
        if dof == 5 and axis == "yaw":
            carried = (origin, mass)
            continue
        if carried:
            origin = tuple(a + b for a, b in zip(origin, carried[0]))
            mass += carried[1]
            carried = None
        if k < 2:
            lname = "hip_" + axis + "_link"
        spec.append((name, AXES[axis], origin, lim, effort, velocity, (lname, mass, com, size)))
    knee = LEG[3]
    if carried:  # the yaw was the last hip joint: its offset and link go to the knee's chain
        knee = (knee[0], knee[1], tuple(a + b for a, b in zip(knee[2], carried[0])), knee[3],
                knee[4], knee[5], knee[6])
        last = spec[-1]
        spec[-1] = last[:6] + ((last[6][0], last[6][1] + carried[1], last[6][2], last[6][3]),)
    spec.append(knee)
    for k, axis in enumerate(ankles.split("-")):
        name, _, _, lim, effort, velocity, _ = ankle["ankle_" + axis]
        _, _, origin, _, _, _, (lname, mass, com, size) = LEG[4 + k]
        if k == 0:
            lname = "ankle_link"
        spec.append((name, AXES[axis], origin, lim, effort, velocity, (lname, mass, com, size)))
    return spec


def scaled(spec, scale):
    return [(j, a, o, lim, e * scale, v, (n, m * scale, c, sz))
            for j, a, o, lim, e, v, (n, m, c, sz) in spec]


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
    ap.add_argument("--hips", default="yaw-roll-pitch",
                    choices=["yaw-roll-pitch", "pitch-roll-yaw", "roll-pitch-yaw", "yaw-pitch-roll"],
                    help="the hip joints' order from the pelvis down")
    ap.add_argument("--ankles", default="pitch-roll", choices=["pitch-roll", "roll-pitch"],
                    help="the ankle joints' order from the shin down")
    ap.add_argument("--leg-dof", type=int, default=6, choices=[5, 6],
                    help="joints per leg (5: no hip yaw)")
    ap.add_argument("--waist-dof", type=int, default=0, choices=[0, 3],
                    help="waist joints between pelvis and torso (0: fixed)")
    ap.add_argument("--arm-dof", type=int, default=6, choices=[6, 7],
                    help="joints per arm (7: a wrist roll)")
    ap.add_argument("--total-mass", type=float, default=0.0,
                    help="scale every mass (and effort limit) to this total, kg")
    ap.add_argument("--vendor-quirks", action="store_true",
                    help="write the file as vendors do: CRLF line endings, mesh visuals, "
                         "<gazebo>, <transmission> and <mujoco> elements, a mimic joint on each "
                         "hand (a finger) and a massless camera link on a revolute joint")
    ap.add_argument("-o", "--output", help="write here instead of standard output")
    args = ap.parse_args()
    frames = not args.no_frame_links
    global POINT_FEET, QUIRKS
    POINT_FEET = args.point_feet
    QUIRKS = args.vendor_quirks
    base_mass = (sum(m for m, _, _ in TRUNK.values()) + 2 * sum(j[6][1] for j in LEG + ARM))
    extra = 2 * WAIST[0][6][1] if args.waist_dof else 0.0
    extra += 2 * WRIST_ROLL[6][1] if args.arm_dof == 7 else 0.0
    extra += 2 * FINGER_MASS if QUIRKS else 0.0
    scale = args.total_mass / (base_mass + extra) if args.total_mass > 0 else 1.0
    leg = scaled(leg_spec(args.hips, args.ankles, args.leg_dof), scale)
    arm = ARM
    if args.arm_dof == 7:  # a small link between wrist pitch and roll; the hand on the roll
        arm = ARM[:5] + [ARM[5][:6] + (WRIST_ROLL[6],), WRIST_ROLL[:6] + (ARM[5][6],)]
    arm = scaled(arm, scale)
    parts, table = [], []
    for name, (mass, com, size) in TRUNK.items():
        parts.append(link(name, mass * scale, com, size))
        table.append((name, mass * scale, "trunk"))
    if args.waist_dof:
        parent = "pelvis"
        for joint, axis, origin, lim, effort, velocity, (lname, mass, com, size) in scaled(WAIST, scale):
            parts.append(link(lname, mass, com, size))
            parts.append(revolute(joint, parent, lname, origin, axis, lim, effort, velocity))
            table.append((lname, mass, "trunk"))
            parent = lname
        joint, axis, origin, lim, effort, velocity = WAIST_PITCH
        parts.append(revolute(joint, parent, "torso", origin, axis, lim, effort * scale, velocity))
    else:
        parts.append(fixed("waist", "pelvis", "torso", (0.0, 0.0, 0.10)))
    parts.append(fixed("neck", "torso", "head", (0.0, 0.0, 0.45)))
    if QUIRKS:  # a camera that tilts, its link without <inertial> (a sensor, as vendors write it)
        parts.append('  <link name="head_camera"/>\n')
        parts.append(revolute("head_camera_tilt", "head", "head_camera", (0.08, 0.0, 0.05),
                              "0 1 0", (-0.5, 0.5), 1, 1))
    if frames:
        parts.append(frame_link("imu"))
        parts.append(fixed("imu_mount", "pelvis", "imu", (0.0, 0.0, 0.04)))
        parts.append(frame_link("lidar"))
        parts.append(fixed("lidar_mount", "head", "lidar", (0.08, 0.0, 0.10)))
    for side in (LEFT, RIGHT):
        out, foot, masses = chain(side, "pelvis", leg)
        parts += out
        table += [(n, m, "leg") for n, m in masses]
        prefix = "left_" if side == LEFT else "right_"
        for contact, pos in CONTACTS.items() if frames else ():
            parts.append(frame_link(prefix + contact))
            parts.append(fixed(prefix + contact + "_mount", foot, prefix + contact, pos))
    for side in (LEFT, RIGHT):
        out, hand, masses = chain(side, "torso", arm)
        parts += out
        table += [(n, m, "arm") for n, m in masses]
        if QUIRKS:  # a finger that follows the wrist pitch (a mimic joint: no motor of its own)
            prefix = "left_" if side == LEFT else "right_"
            finger = prefix + "finger"
            parts.append(link(finger, FINGER_MASS * scale, (0.0, 0.0, -0.02), (0.02, 0.02, 0.04)))
            parts.append(revolute(prefix + "finger_joint", hand, finger, (0.0, 0.0, -0.14),
                                  "0 1 0", (-0.5, 0.5), 2, 5,
                                  mimic=(prefix + "wrist_pitch", 0.5, 0.0)))
            table.append((finger, FINGER_MASS * scale, "arm"))
    if QUIRKS:
        parts.append('  <gazebo reference="pelvis">\n    <mu1>0.8</mu1>\n  </gazebo>\n')
        parts.append('  <transmission name="left_knee_transmission">\n'
                     '    <type>transmission_interface/SimpleTransmission</type>\n'
                     '    <joint name="left_knee"><hardwareInterface>EffortJointInterface'
                     '</hardwareInterface></joint>\n  </transmission>\n')
        parts.append('  <mujoco>\n    <compiler meshdir="meshes" discardvisual="false"/>\n'
                     '  </mujoco>\n')

    total = sum(m for _, m, _ in table)
    limbs = sum(m for _, m, g in table if g != "trunk")
    lines = ["  Link masses (kg):"]
    lines += [f"    {n:<28} {m:6.2f}  {g}" for n, m, g in table]
    lines += [f"    {'total':<28} {total:6.2f}",
              f"    {'limbs (legs + arms)':<28} {limbs:6.2f}  ({100 * limbs / total:.1f} % of total)"]
    # Vendors' files come from Windows tools as often as not: CRLF line endings.
    out = open(args.output, "w", newline="\r\n" if QUIRKS else None) if args.output else sys.stdout
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
