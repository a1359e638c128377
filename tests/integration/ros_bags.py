"""Writes small synthetic ROS 1 bags for the rosbag import tests (helper of test_ros_rosbag_import.py).

Runs on Debian's interpreter with python3-rosbag, genpy and genmsg. The message classes are generated at run time
from the .msg files the -dev packages install under /usr/share/<package>/msg (Debian packages no python3-sensor-msgs
here); tf2_msgs/TFMessage, whose .msg Debian does not install, is its one-line definition. The checksums are
genmsg's, the same the C++ headers carry (the importer's instantiate<> refuses a mismatch).

The scene: a closed room with a table and a cabinet, seen by a depth camera 1 m above the floor, tilted 15 degrees
down. The camera holds still at place A, drives 3 m in 12 frames to place B, holds still there (8 Hz stamps,
multiples of 1/8 s, exact in binary). Depth is ray cast exactly and jittered with seeded noise; poses too.
"""

import math
import os
import random
import struct
import tempfile

import genmsg
import genmsg.msg_loader
import genpy
import genpy.dynamic
import rosbag

T0_S = 1000  # stamp of the first frame with a pose [s]
HZ = 8
WIDTH, HEIGHT, FX, FY, CX, CY = 80, 60, 60.0, 60.0, 39.5, 29.5
HOLD_A, DRIVE, HOLD_B = 24, 12, 24  # frames; the drive's last frame is the first at B (counted in HOLD_B)
EARLY = 2  # depth images stamped before the first odom -> base_link transform: no pose, skipped
# The base in the map at the two places: x, y [m], yaw [rad].
PLACE_A = (-1.5, -1.0, math.radians(60))
PLACE_B = (1.5, -1.0, math.radians(120))
MAP_ODOM = (0.2, -0.1, 0.05)  # the localisation's map -> odom (x, y, yaw)
BASE_CAMERA_XYZ = (0.1, 0.0, 1.0)
CAMERA_PITCH = math.radians(15)
# Axis-aligned boxes of the scene (min corner, max corner) [m, map frame]; the room is seen from inside.
ROOM = ((-3.5, -3.0, 0.0), (3.5, 3.0, 2.6))
FURNITURE = [((-0.5, 0.8, 0.0), (0.5, 1.6, 0.75)), ((2.6, 1.0, 0.0), (3.2, 2.0, 1.2))]

_TYPES = ["sensor_msgs/Image", "sensor_msgs/CameraInfo", "tf2_msgs/TFMessage", "geometry_msgs/TransformStamped"]


def message_classes():
    """{type name: generated class} for the types the bags use."""
    tf2_dir = tempfile.mkdtemp(prefix="tf2_msgs-")
    os.makedirs(os.path.join(tf2_dir, "tf2_msgs", "msg"))
    with open(os.path.join(tf2_dir, "tf2_msgs", "msg", "TFMessage.msg"), "w") as f:
        f.write("geometry_msgs/TransformStamped[] transforms\n")
    search = {p: ["/usr/share/%s/msg" % p] for p in ("std_msgs", "geometry_msgs", "sensor_msgs")}
    search["tf2_msgs"] = [os.path.join(tf2_dir, "tf2_msgs", "msg")]
    context = genmsg.MsgContext.create_default()
    classes = {}
    for name in _TYPES:
        spec = genmsg.msg_loader.load_msg_by_type(context, name, search)
        genmsg.msg_loader.load_depends(context, spec, search)
        classes[name] = genpy.dynamic.generate_dynamic(name, genmsg.compute_full_text(context, spec))[name]
    return classes


# ------------------------------------------------------------------------------------------------ geometry


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def rot_z(yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    return [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]


def rot_y(pitch):
    c, s = math.cos(pitch), math.sin(pitch)
    return [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]


# camera_link (x forward, z up) -> optical frame (z forward, x right, y down)
R_LINK_OPTICAL = [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]


def compose(x_ab, x_bc):
    """Poses as (R, t): X_AC = X_AB * X_BC."""
    r_ab, t_ab = x_ab
    r_bc, t_bc = x_bc
    return mat_mul(r_ab, r_bc), [a + b for a, b in zip(mat_vec(r_ab, t_bc), t_ab)]


def inverse(x):
    r, t = x
    rt = [[r[j][i] for j in range(3)] for i in range(3)]
    return rt, [-v for v in mat_vec(rt, t)]


def planar(x, y, yaw):
    return rot_z(yaw), [x, y, 0.0]


def quaternion(r):
    """(x, y, z, w) of a rotation matrix (Shepperd's method)."""
    trace = r[0][0] + r[1][1] + r[2][2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        return ((r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s, 0.25 * s)
    i = max(range(3), key=lambda k: r[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + r[i][i] - r[j][j] - r[k][k])
    q = [0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (r[j][i] + r[i][j]) / s
    q[k] = (r[k][i] + r[i][k]) / s
    return (q[0], q[1], q[2], (r[k][j] - r[j][k]) / s)


def base_camera():
    """X_BaseCameraLink and X_CameraLinkOptical."""
    return (rot_y(CAMERA_PITCH), list(BASE_CAMERA_XYZ)), (R_LINK_OPTICAL, [0.0, 0.0, 0.0])


def optical_in_map(base_pose):
    link, optical = base_camera()
    return compose(compose(planar(*base_pose), link), optical)


# ------------------------------------------------------------------------------------------------ trajectory


def trajectory(seed):
    """[(stamp in s, base pose (x, y, yaw) in the map)] for the frames with a pose: hold at A, drive, hold at B.
    Seeded jitter of 2 mm / 1 mrad (a robot standing still is not perfectly still)."""
    rng = random.Random(seed)
    out = []
    for k in range(HOLD_A + DRIVE - 1 + HOLD_B):
        if k < HOLD_A:
            x, y, yaw = PLACE_A
        elif k < HOLD_A + DRIVE:
            f = (k - HOLD_A + 1) / DRIVE
            x, y, yaw = [a + f * (b - a) for a, b in zip(PLACE_A, PLACE_B)]
        else:
            x, y, yaw = PLACE_B
        out.append((T0_S + k / HZ, (x + rng.gauss(0, 0.002), y + rng.gauss(0, 0.002), yaw + rng.gauss(0, 0.001))))
    return out


# ------------------------------------------------------------------------------------------------ depth


def _box_exit(origin, d, lo, hi):
    """Distance along d at which a ray from inside the box leaves it."""
    t = math.inf
    for a in range(3):
        if d[a] > 1e-12:
            t = min(t, (hi[a] - origin[a]) / d[a])
        elif d[a] < -1e-12:
            t = min(t, (lo[a] - origin[a]) / d[a])
    return t


def _box_entry(origin, d, lo, hi):
    """Distance along d at which a ray from outside enters the box, or inf (slab test)."""
    t_near, t_far = -math.inf, math.inf
    for a in range(3):
        if abs(d[a]) < 1e-12:
            if origin[a] < lo[a] or origin[a] > hi[a]:
                return math.inf
            continue
        t1, t2 = (lo[a] - origin[a]) / d[a], (hi[a] - origin[a]) / d[a]
        t_near, t_far = max(t_near, min(t1, t2)), min(t_far, max(t1, t2))
    return t_near if 0 < t_near <= t_far else math.inf


def depth_metres(x_map_optical, rng, noise_m=0.002, camera=None):
    """Row-major depth [m] (along the optical axis) of the scene seen from X_MapOptical, with seeded noise.
    camera: (width, height, fx, fy, cx, cy), default the bags' 80 x 60 camera."""
    width, height, fx, fy, cx, cy = camera or (WIDTH, HEIGHT, FX, FY, CX, CY)
    r, origin = x_map_optical
    out = []
    for v in range(height):
        for u in range(width):
            d = mat_vec(r, [(u - cx) / fx, (v - cy) / fy, 1.0])  # t along d is the depth itself
            t = _box_exit(origin, d, *ROOM)
            for lo, hi in FURNITURE:
                t = min(t, _box_entry(origin, d, lo, hi))
            out.append(t + rng.gauss(0, noise_m))
    return out


def surface_distance(p):
    """Distance [m] from a point to the nearest surface of the scene (room walls, floor, ceiling, furniture)."""
    lo, hi = ROOM
    best = min(min(abs(p[a] - lo[a]), abs(p[a] - hi[a])) for a in range(3))
    for lo, hi in FURNITURE:
        outside = [max(lo[a] - p[a], 0.0, p[a] - hi[a]) for a in range(3)]
        if any(outside):
            best = min(best, math.sqrt(sum(o * o for o in outside)))
        else:
            best = min(best, min(min(p[a] - lo[a], hi[a] - p[a]) for a in range(3)))
    return best


# ------------------------------------------------------------------------------------------------ bags

# The two layouts: the robot's (tf tree map -> odom -> base_link -> camera_link -> camera_depth_optical_frame, the
# camera mount on /tf_static, 16UC1 millimetres) and the TUM RGB-D benchmark's (/world -> /kinect -> /openni_camera
# -> /openni_rgb_optical_frame, everything on /tf with leading slashes, 32FC1 metres with NaN for no reading).
ROBOT = {"depth": "/camera/depth/image_rect_raw", "info": "/camera/depth/camera_info", "encoding": "16UC1",
         "frames": ("map", "odom", "base_link", "camera_link", "camera_depth_optical_frame"), "static": True}
TUM = {"depth": "/camera/depth/image", "info": "/camera/depth/camera_info", "encoding": "32FC1",
       "frames": ("/world", None, "/kinect", "/openni_camera", "/openni_rgb_optical_frame"), "static": False}


class Writer:
    """Writes tf, CameraInfo and depth Image messages into an open rosbag.Bag (camera: width, height, fx, fy, cx, cy)."""

    def __init__(self, bag, classes, camera=None):
        self.bag, self.c = bag, classes
        self.camera = camera or (WIDTH, HEIGHT, FX, FY, CX, CY)

    def transform(self, stamp, parent, child, x):
        t = self.c["geometry_msgs/TransformStamped"]()
        t.header.stamp, t.header.frame_id, t.child_frame_id = stamp, parent, child
        r, p = x
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = p
        q = quaternion(r)
        t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w = q
        return t

    def tf(self, topic, stamp, transforms):
        msg = self.c["tf2_msgs/TFMessage"]()
        msg.transforms = transforms
        self.bag.write(topic, msg, t=stamp)

    def info(self, topic, stamp, frame):
        msg = self.c["sensor_msgs/CameraInfo"]()
        msg.header.stamp, msg.header.frame_id = stamp, frame
        width, height, fx, fy, cx, cy = self.camera
        msg.width, msg.height, msg.distortion_model = width, height, "plumb_bob"
        msg.D = [0.0] * 5
        msg.K = [fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0]
        msg.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        msg.P = [fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0]
        self.bag.write(topic, msg, t=stamp)

    def image(self, topic, stamp, frame, encoding, depth_m):
        msg = self.c["sensor_msgs/Image"]()
        msg.header.stamp, msg.header.frame_id = stamp, frame
        width, height = self.camera[:2]
        msg.width, msg.height, msg.encoding, msg.is_bigendian = width, height, encoding, 0
        if encoding == "32FC1":  # metres; the first column has no reading (NaN)
            values = [math.nan if i % width == 0 else d for i, d in enumerate(depth_m)]
            msg.step, msg.data = 4 * width, struct.pack("<%df" % len(values), *values)
        elif encoding in ("16UC1", "mono16"):  # millimetres; the first column has no reading (0)
            values = [0 if i % width == 0 else max(0, min(65535, round(d * 1000))) for i, d in enumerate(depth_m)]
            msg.step, msg.data = 2 * width, struct.pack("<%dH" % len(values), *values)
        else:  # an encoding the importer does not know: 3 bytes a pixel
            msg.step, msg.data = 3 * width, bytes(3 * width * height)
        self.bag.write(topic, msg, t=stamp)


def write_bag(path, layout, seed, encoding=None, with_info=True, with_tf=True):
    """Writes the scene's bag in `layout` (ROBOT or TUM); returns the frames with a pose as [(stamp s, X_MapOptical)].
    encoding overrides the layout's; with_info / with_tf False leave out the camera info topic / every tf message."""
    classes = message_classes()
    frames = layout["frames"]
    encoding = encoding or layout["encoding"]
    link, optical = base_camera()
    map_odom = planar(*MAP_ODOM)
    rng = random.Random(seed)
    poses = trajectory(seed)
    expected = []
    with rosbag.Bag(path, "w") as bag:
        w = Writer(bag, classes)
        start = genpy.Time.from_sec(T0_S - 1.0)
        if with_tf and layout["static"]:
            w.tf("/tf_static", start, [w.transform(start, frames[2], frames[3], link),
                                       w.transform(start, frames[3], frames[4], optical)])
        stamps = [T0_S - (EARLY - k) / HZ for k in range(EARLY)] + [s for s, _ in poses]
        for k, stamp_s in enumerate(stamps):
            stamp = genpy.Time.from_sec(stamp_s)
            base = poses[k - EARLY][1] if k >= EARLY else poses[0][1]
            x_map_optical = optical_in_map(base)
            if with_tf and k >= EARLY:
                tf = []
                if frames[1]:  # map -> odom -> base_link (the localisation and the odometry)
                    tf.append(w.transform(stamp, frames[0], frames[1], map_odom))
                    tf.append(w.transform(stamp, frames[1], frames[2], compose(inverse(map_odom), planar(*base))))
                else:  # the motion capture gives the base in the world directly
                    tf.append(w.transform(stamp, frames[0], frames[2], planar(*base)))
                if not layout["static"]:
                    tf += [w.transform(stamp, frames[2], frames[3], link), w.transform(stamp, frames[3], frames[4], optical)]
                w.tf("/tf", stamp, tf)
                expected.append((stamp_s, x_map_optical))
            if with_info:
                w.info(layout["info"], stamp, frames[4])
            w.image(layout["depth"], stamp, frames[4], encoding, depth_metres(x_map_optical, rng))
    return expected
