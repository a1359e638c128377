"""Writes small synthetic ROS 1 bags for the rosbag import and bridge tests (helper of test_ros_rosbag_import.py and
test_ros_bridge.py).

Runs on Debian's interpreter with python3-rosbag, genpy, genmsg and numpy. The message classes are generated at run
time from the .msg files the -dev packages install under /usr/share/<package>/msg (Debian packages no
python3-sensor-msgs here); tf2_msgs/TFMessage, whose .msg Debian does not install, is its one-line definition. The
checksums are genmsg's, the same the C++ headers carry (the importer's instantiate<> refuses a mismatch).

The scene: a closed room with a table and a cabinet, seen by a 160 x 120 depth camera 1.4 m above the floor, tilted
35 degrees down. Two visits to the table with a pause elsewhere between them: the camera holds still at place A
(1 m in front of the table), drives to place B, holds still there, drives back to A and holds still again (8 Hz
stamps, multiples of 1/8 s, exact in binary). A key box appears on the table while the camera is away (it is there
from the drive back on); during the second stay at A a person walks in beside the table and out again, and the bag
can carry a person mask of them (mono8, 255 on their pixels). Depth is ray cast exactly (numpy) and jittered with
seeded noise; poses too. The bag can also carry the room's nav_msgs/OccupancyGrid once at its start.
"""

import math
import os
import random
import tempfile

import genmsg
import genmsg.msg_loader
import genpy
import genpy.dynamic
import numpy as np
import rosbag

T0_S = 1000  # stamp of the first frame with a pose [s]
HZ = 8
WIDTH, HEIGHT, FX, FY, CX, CY = 160, 120, 120.0, 120.0, 79.5, 59.5
# Frames of each part; a drive's last frame is the first at its destination (counted in the hold that follows).
HOLD_A, DRIVE, HOLD_B, HOLD_A2 = 24, 12, 24, 24
EARLY = 2  # depth images stamped before the first odom -> base_link transform: no pose, skipped
# The base in the map at the two places: x, y [m], yaw [rad].
PLACE_A = (0.0, -0.3, math.radians(90))
PLACE_B = (2.0, -1.5, math.radians(150))
MAP_ODOM = (0.2, -0.1, 0.05)  # the localisation's map -> odom (x, y, yaw)
BASE_CAMERA_XYZ = (0.1, 0.0, 1.4)
CAMERA_PITCH = math.radians(35)
# Axis-aligned boxes of the scene (min corner, max corner) [m, map frame]; the room is seen from inside.
ROOM = ((-3.5, -3.0, 0.0), (3.5, 3.0, 2.6))
FURNITURE = [((-0.5, 0.8, 0.0), (0.5, 1.6, 0.75)), ((2.6, 1.0, 0.0), (3.2, 2.0, 1.2))]
# The key box on the table, there from the drive back to A on (20 x 15 x 15 cm: about 310 pixels from A at 160 x 120;
# a 14 x 10 x 6 cm box, under 100 pixels, is too small for the merge of the second visit at this resolution: its
# pixels lie within the pose tolerance window of the table top in front of it and stay background).
KEY = ((0.0, 1.0, 0.75), (0.2, 1.15, 0.9))
KEY_CENTRE = tuple((a + b) / 2 for a, b in zip(*KEY))
# The person beside the table during the second stay at A, frames PERSON_FRAMES of that hold (0-based).
PERSON = ((0.55, 1.8, 0.0), (0.85, 2.1, 1.7))
PERSON_FRAMES = range(15, 20)
MASK_TOPIC = "/camera/person_mask"
# Server settings for these bags, given to every anchordb process that stores or analyses them (import and server):
# the smallest change segment is 250 pixels by default, meant for 640 x 480; the key box has about 200 points at
# 160 x 120 and a 17-point sliver of its top can come apart from it, so 50.
SERVER_SETTINGS = ["--segment_min_points=50"]
GRID_TOPIC = "/map"
GRID_RESOLUTION_M = 0.1

_TYPES = ["sensor_msgs/Image", "sensor_msgs/CameraInfo", "tf2_msgs/TFMessage", "geometry_msgs/TransformStamped",
          "nav_msgs/OccupancyGrid"]


def message_classes():
    """{type name: generated class} for the types the bags use."""
    tf2_dir = tempfile.mkdtemp(prefix="tf2_msgs-")
    os.makedirs(os.path.join(tf2_dir, "tf2_msgs", "msg"))
    with open(os.path.join(tf2_dir, "tf2_msgs", "msg", "TFMessage.msg"), "w") as f:
        f.write("geometry_msgs/TransformStamped[] transforms\n")
    search = {p: ["/usr/share/%s/msg" % p] for p in ("std_msgs", "geometry_msgs", "sensor_msgs", "nav_msgs")}
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


def stays():
    """[(first frame index, frame count, place)] of the holds, frame indices among the frames with a pose."""
    a2 = HOLD_A + DRIVE - 1 + HOLD_B + DRIVE - 1
    return [(0, HOLD_A, PLACE_A), (HOLD_A + DRIVE - 1, HOLD_B, PLACE_B), (a2, HOLD_A2, PLACE_A)]


FRAMES_WITH_POSE = HOLD_A + DRIVE - 1 + HOLD_B + DRIVE - 1 + HOLD_A2


def trajectory(seed):
    """[(stamp in s, base pose (x, y, yaw) in the map)] for the frames with a pose: hold at A, drive to B, hold at B,
    drive back, hold at A. Seeded jitter of 2 mm / 1 mrad (a robot standing still is not perfectly still)."""
    rng = random.Random(seed)
    legs = [(PLACE_A, PLACE_A, HOLD_A), (PLACE_A, PLACE_B, DRIVE - 1), (PLACE_B, PLACE_B, HOLD_B),
            (PLACE_B, PLACE_A, DRIVE - 1), (PLACE_A, PLACE_A, HOLD_A2)]
    out = []
    for start, end, n in legs:
        for j in range(n):
            f = (j + 1) / DRIVE if start != end else 0.0
            x, y, yaw = [a + f * (b - a) for a, b in zip(start, end)]
            k = len(out)
            out.append((T0_S + k / HZ, (x + rng.gauss(0, 0.002), y + rng.gauss(0, 0.002), yaw + rng.gauss(0, 0.001))))
    return out


def scene_at(k):
    """The boxes in the room besides the furniture at frame k (index among the frames with a pose; negative: before
    the first): the key from the drive back on, the person during PERSON_FRAMES of the second stay at A."""
    b_end = HOLD_A + DRIVE - 1 + HOLD_B
    a2 = stays()[2][0]
    boxes = []
    if k >= b_end:
        boxes.append(KEY)
    if k - a2 in PERSON_FRAMES:
        boxes.append(PERSON)
    return boxes


# ------------------------------------------------------------------------------------------------ depth


def _rays(x_map_optical, camera):
    width, height, fx, fy, cx, cy = camera
    r, origin = x_map_optical
    u, v = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
    d_cam = np.stack([(u - cx) / fx, (v - cy) / fy, np.ones_like(u)], axis=-1).reshape(-1, 3)
    return np.asarray(origin, dtype=np.float64), d_cam @ np.asarray(r, dtype=np.float64).T  # t along d is the depth


def _box_exit(origin, d, lo, hi):
    """Distance along each ray at which it leaves the box it starts in."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t_hi = (np.asarray(hi) - origin) / d
        t_lo = (np.asarray(lo) - origin) / d
    t = np.where(d > 1e-12, t_hi, np.where(d < -1e-12, t_lo, np.inf))
    return t.min(axis=1)


def _box_entry(origin, d, lo, hi):
    """Distance along each ray at which it enters the box from outside, or inf (slab test)."""
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    parallel = np.abs(d) < 1e-12
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (lo - origin) / d, (hi - origin) / d
    t_min = np.where(parallel, -np.inf, np.minimum(t1, t2))
    t_max = np.where(parallel, np.inf, np.maximum(t1, t2))
    outside = parallel & ((origin < lo) | (origin > hi))
    t_near, t_far = t_min.max(axis=1), t_max.min(axis=1)
    hit = (t_near > 0) & (t_near <= t_far) & ~outside.any(axis=1)
    return np.where(hit, t_near, np.inf)


def render(x_map_optical, boxes=(), camera=None):
    """Exact depth [m] (along the optical axis, row-major, numpy) of the room, its furniture and `boxes` seen from
    X_MapOptical, and the index into `boxes` of what each pixel sees (-1: room or furniture).
    camera: (width, height, fx, fy, cx, cy), default the bags' 160 x 120 camera."""
    origin, d = _rays(x_map_optical, camera or (WIDTH, HEIGHT, FX, FY, CX, CY))
    t = _box_exit(origin, d, *ROOM)
    for lo, hi in FURNITURE:
        t = np.minimum(t, _box_entry(origin, d, lo, hi))
    which = np.full(t.shape, -1)
    for i, (lo, hi) in enumerate(boxes):
        e = _box_entry(origin, d, lo, hi)
        which = np.where(e < t, i, which)
        t = np.minimum(t, e)
    return t, which


def depth_metres(x_map_optical, rng, noise_m=0.002, camera=None, boxes=()):
    """Row-major depth [m] of the scene (and `boxes`) seen from X_MapOptical, with seeded noise (numpy, from rng).
    camera: (width, height, fx, fy, cx, cy), default the bags' camera."""
    t, _ = render(x_map_optical, boxes, camera)
    if noise_m:
        t = t + np.random.default_rng(rng.getrandbits(64)).normal(0.0, noise_m, t.shape)
    return t


def surface_distance(p):
    """Distance [m] from a point to the nearest surface of the scene (room walls, floor, ceiling, furniture, key)."""
    lo, hi = ROOM
    best = min(min(abs(p[a] - lo[a]), abs(p[a] - hi[a])) for a in range(3))
    for lo, hi in FURNITURE + [KEY]:
        outside = [max(lo[a] - p[a], 0.0, p[a] - hi[a]) for a in range(3)]
        if any(outside):
            best = min(best, math.sqrt(sum(o * o for o in outside)))
        else:
            best = min(best, min(min(p[a] - lo[a], hi[a] - p[a]) for a in range(3)))
    return best


def occupancy_cells():
    """The room as nav_msgs/OccupancyGrid cells (row-major from the origin, ROOM's min corner, GRID_RESOLUTION_M):
    100 on the walls' ring and under the furniture, 0 elsewhere, -1 (unknown) in the room's far left quarter, so all
    three values occur."""
    (x0, y0, _), (x1, y1, _) = ROOM
    width, height = round((x1 - x0) / GRID_RESOLUTION_M), round((y1 - y0) / GRID_RESOLUTION_M)
    cells = []
    for r in range(height):
        for c in range(width):
            x, y = x0 + (c + 0.5) * GRID_RESOLUTION_M, y0 + (r + 0.5) * GRID_RESOLUTION_M
            wall = r in (0, height - 1) or c in (0, width - 1)
            furniture = any(lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1] for lo, hi in FURNITURE)
            unknown = c < width // 4 and r > height // 2
            cells.append(100 if wall or furniture else -1 if unknown else 0)
    return width, height, cells


def trinary_pgm(width, height, cells):
    """The binary PGM (as anchordb exports it) of map_server's trinary image of OccupancyGrid cells: 0 occupied
    (>= 65), 254 free (<= 19), 205 unknown (-1 or between); top row = largest y."""
    grey = [205 if v < 0 else 0 if v >= 65 else 254 if v <= 19 else 205 for v in cells]
    rows = [bytes(grey[r * width:(r + 1) * width]) for r in range(height)]
    return b"P5\n%d %d\n255\n" % (width, height) + b"".join(reversed(rows))


# ------------------------------------------------------------------------------------------------ bags

# The two layouts: the robot's (tf tree map -> odom -> base_link -> camera_link -> camera_depth_optical_frame, the
# camera mount on /tf_static, 16UC1 millimetres) and the TUM RGB-D benchmark's (/world -> /kinect -> /openni_camera
# -> /openni_rgb_optical_frame, everything on /tf with leading slashes, 32FC1 metres with NaN for no reading).
ROBOT = {"depth": "/camera/depth/image_rect_raw", "info": "/camera/depth/camera_info", "encoding": "16UC1",
         "frames": ("map", "odom", "base_link", "camera_link", "camera_depth_optical_frame"), "static": True}
TUM = {"depth": "/camera/depth/image", "info": "/camera/depth/camera_info", "encoding": "32FC1",
       "frames": ("/world", None, "/kinect", "/openni_camera", "/openni_rgb_optical_frame"), "static": False}


class Writer:
    """Writes tf, CameraInfo, depth / mask Image and OccupancyGrid messages into an open rosbag.Bag (camera: width,
    height, fx, fy, cx, cy)."""

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
        depth = np.asarray(depth_m, dtype=np.float64).reshape(height, width)
        if encoding == "32FC1":  # metres; the first column has no reading (NaN)
            values = depth.astype("<f4")
            values[:, 0] = np.nan
            msg.step, msg.data = 4 * width, values.tobytes()
        elif encoding in ("16UC1", "mono16"):  # millimetres; the first column has no reading (0)
            values = np.clip(np.round(depth * 1000), 0, 65535).astype("<u2")
            values[:, 0] = 0
            msg.step, msg.data = 2 * width, values.tobytes()
        else:  # an encoding the importer does not know: 3 bytes a pixel
            msg.step, msg.data = 3 * width, bytes(3 * width * height)
        self.bag.write(topic, msg, t=stamp)

    def mask(self, topic, stamp, frame, pixels):
        """A mono8 mask: 255 where `pixels` (row-major booleans) is true, else 0."""
        msg = self.c["sensor_msgs/Image"]()
        msg.header.stamp, msg.header.frame_id = stamp, frame
        width, height = self.camera[:2]
        msg.width, msg.height, msg.encoding, msg.is_bigendian, msg.step = width, height, "mono8", 0, width
        msg.data = np.where(np.asarray(pixels), 255, 0).astype(np.uint8).tobytes()
        self.bag.write(topic, msg, t=stamp)

    def grid(self, topic, stamp, frame):
        """The room's OccupancyGrid (occupancy_cells)."""
        msg = self.c["nav_msgs/OccupancyGrid"]()
        msg.header.stamp, msg.header.frame_id = stamp, frame
        width, height, cells = occupancy_cells()
        msg.info.map_load_time = stamp
        msg.info.resolution, msg.info.width, msg.info.height = GRID_RESOLUTION_M, width, height
        msg.info.origin.position.x, msg.info.origin.position.y = ROOM[0][0], ROOM[0][1]
        msg.info.origin.orientation.w = 1.0
        msg.data = cells
        self.bag.write(topic, msg, t=stamp)


def write_bag(path, layout, seed, encoding=None, with_info=True, with_tf=True, with_mask=False, with_grid=False):
    """Writes the scene's bag in `layout` (ROBOT or TUM); returns the frames with a pose as [(stamp s, X_MapOptical)].
    encoding overrides the layout's; with_info / with_tf False leave out the camera info topic / every tf message;
    with_mask adds the person mask (MASK_TOPIC, one per depth image, same stamp, before it); with_grid the room's
    OccupancyGrid on GRID_TOPIC once, before the first image."""
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
        if with_grid:
            w.grid(GRID_TOPIC, start, frames[0])
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
            boxes = scene_at(k - EARLY)
            depth, which = render(x_map_optical, boxes)
            depth = depth + np.random.default_rng(rng.getrandbits(64)).normal(0.0, 0.002, depth.shape)
            if with_mask:
                person = [i for i, b in enumerate(boxes) if b is PERSON]
                w.mask(MASK_TOPIC, stamp, frames[4], np.isin(which, person))
            w.image(layout["depth"], stamp, frames[4], encoding, depth)
    return expected
