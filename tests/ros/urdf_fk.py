"""A small URDF reader and forward kinematics (numpy only), for the project's
plain URDF (ros/tactile_ros/urdf/lwr4plus_wts.urdf): links, joints (revolute,
continuous, prismatic, fixed) with origin xyz/rpy and axis, limits, inertials
and box visuals, as the URDF specification defines them:

  {parent}T{child} = Trans(origin.xyz) * Rot(origin.rpy) * JointMotion(axis, q)
  Rot(r, p, y) = Rz(y) Ry(p) Rx(r)       (fixed axes x, y, z; KDL::Rotation::RPY)

Used by tests/ros/check_urdf.py (the URDF against the simulator's kinematics)
and tests/ros/check_topics.py (the published joint states through the URDF
against the published flange pose).
"""
import xml.etree.ElementTree as ET

import numpy as np


def rot_rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def rot_axis(axis, angle):
    """Rodrigues: rotation by angle (rad) about the unit vector axis."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def transform(rot=None, pos=None):
    t = np.eye(4)
    if rot is not None:
        t[:3, :3] = rot
    if pos is not None:
        t[:3, 3] = pos
    return t


def _floats(text, n, what):
    v = [float(x) for x in text.split()]
    if len(v) != n:
        raise ValueError(f"{what}: need {n} numbers, got '{text}'")
    return np.array(v)


def _origin(elem):
    o = elem.find("origin") if elem is not None else None
    if o is None:
        return np.zeros(3), np.zeros(3)
    return _floats(o.get("xyz", "0 0 0"), 3, "origin xyz"), _floats(o.get("rpy", "0 0 0"), 3, "origin rpy")


class Joint:
    def __init__(self, elem):
        self.name = elem.get("name")
        self.type = elem.get("type")
        self.parent = elem.find("parent").get("link")
        self.child = elem.find("child").get("link")
        self.xyz, self.rpy = _origin(elem)
        ax = elem.find("axis")
        self.axis = _floats(ax.get("xyz"), 3, f"joint {self.name} axis") if ax is not None else np.array([1.0, 0, 0])
        lim = elem.find("limit")
        self.limit = None
        if lim is not None:
            self.limit = {k: float(lim.get(k)) for k in ("lower", "upper", "effort", "velocity") if lim.get(k) is not None}

    def origin(self):
        return transform(rot_rpy(*self.rpy), self.xyz)

    def motion(self, q):
        if self.type in ("revolute", "continuous"):
            return transform(rot_axis(self.axis, q))
        if self.type == "prismatic":
            return transform(pos=np.asarray(self.axis) / np.linalg.norm(self.axis) * q)
        return np.eye(4)


class Link:
    def __init__(self, elem):
        self.name = elem.get("name")
        self.inertial = None
        inert = elem.find("inertial")
        if inert is not None:
            xyz, rpy = _origin(inert)
            i = inert.find("inertia")
            self.inertial = {
                "xyz": xyz,
                "rpy": rpy,
                "mass": float(inert.find("mass").get("value")),
                "inertia": {k: float(i.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")},
            }
        self.boxes = []  # (xyz, rpy, size) of the box visuals
        for v in elem.findall("visual"):
            box = v.find("geometry/box")
            if box is not None:
                xyz, rpy = _origin(v)
                self.boxes.append((xyz, rpy, _floats(box.get("size"), 3, f"link {self.name} box size")))


class Urdf:
    def __init__(self, path):
        root = ET.parse(path).getroot()
        if root.tag != "robot":
            raise ValueError(f"{path}: the root element is <{root.tag}>, not <robot>")
        self.name = root.get("name")
        self.links = {l.get("name"): Link(l) for l in root.findall("link")}
        self.joints = {j.get("name"): Joint(j) for j in root.findall("joint")}
        self.parent_joint = {}
        for j in self.joints.values():
            if j.child in self.parent_joint:
                raise ValueError(f"{path}: link {j.child} has two parent joints")
            for l in (j.parent, j.child):
                if l not in self.links:
                    raise ValueError(f"{path}: joint {j.name} names link {l}, which is not defined")
            self.parent_joint[j.child] = j
        roots = [l for l in self.links if l not in self.parent_joint]
        if len(roots) != 1:
            raise ValueError(f"{path}: {len(roots)} root links ({roots}), need one")
        self.root = roots[0]

    def chain(self, tip):
        """The joints from the root to tip, root first."""
        out = []
        link = tip
        while link != self.root:
            j = self.parent_joint[link]
            out.append(j)
            link = j.parent
        return out[::-1]

    def fk(self, tip, q):
        """{root}T{tip} (4x4) with q a dict joint name -> position (missing: 0)."""
        t = np.eye(4)
        for j in self.chain(tip):
            t = t @ j.origin() @ j.motion(q.get(j.name, 0.0))
        return t

    def relative(self, parent, child, q):
        """{parent}T{child} for a parent on the child's chain."""
        return np.linalg.inv(self.fk(parent, q)) @ self.fk(child, q)


def rotation_angle(r):
    """The angle (rad) of a rotation matrix: |R - I|_F = 2 sqrt(2) sin(angle / 2),
    precise for small angles (arccos of the trace is not: ~1e-8 rad noise)."""
    s = np.linalg.norm(np.asarray(r) - np.eye(3)) / (2.0 * np.sqrt(2.0))
    return float(2.0 * np.arcsin(min(1.0, s)))
