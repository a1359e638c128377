"""A ROS 1 graph for the bridge test (helper of test_ros_bridge.py): a real `rosmaster` on a free loopback port,
started and stopped by PID; the anchordb_ros node as a process; rospy classes of our message and services, generated
at run time from clients/ros/msg and srv (genmsg + genpy.dynamic), and of the ROS messages the test listens to.

Runs on Debian's interpreter (python3-rosmaster, python3-rospy, genpy, genmsg).
"""

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import xmlrpc.client

import genmsg
import genmsg.msg_loader
import genpy.dynamic

ROS_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "clients", "ros")
SEARCH = {p: ["/usr/share/%s/msg" % p] for p in ("std_msgs", "geometry_msgs", "visualization_msgs", "rosgraph_msgs", "nav_msgs")}
SEARCH["anchordb_ros"] = [os.path.join(ROS_DIR, "msg")]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def ros_env(master_port):
    env = dict(os.environ)
    env.update({"ROS_MASTER_URI": "http://127.0.0.1:%d" % master_port, "ROS_HOSTNAME": "127.0.0.1",
                "ROS_LOG_DIR": tempfile.mkdtemp(prefix="ros-log-"), "ROSCONSOLE_STDOUT_LINE_BUFFERED": "1"})
    return env


class Master:
    """`rosmaster --core` on a free loopback port; stop() ends it by its PID."""

    def __init__(self):
        self.port = free_port()
        self.env = ros_env(self.port)
        self.proc = subprocess.Popen(["rosmaster", "--core", "-p", str(self.port)], env=self.env,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.uri = self.env["ROS_MASTER_URI"]
        self.api = xmlrpc.client.ServerProxy(self.uri)
        deadline = time.monotonic() + 20
        while True:
            try:
                self.api.getSystemState("/test")
                return
            except OSError:
                if self.proc.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError("rosmaster did not start on port %d" % self.port)
                time.sleep(0.1)

    def subscribers(self, topic):
        _, _, (_, subscribers, _) = self.api.getSystemState("/test")
        return next((nodes for name, nodes in subscribers if name == topic), [])

    def wait_subscribed(self, node, topics, timeout=20):
        deadline = time.monotonic() + timeout
        while not all(node in self.subscribers(t) for t in topics):
            if time.monotonic() > deadline:
                raise AssertionError("%s did not subscribe to %s" % (node, topics))
            time.sleep(0.1)

    def clear_params(self, namespace):
        """Deletes the parameters under `namespace` (a node's private ones: what `_name:=value` set for an earlier
        node of the same name stays on the parameter server and would be read by the next one)."""
        code, _, present = self.api.hasParam("/test", namespace)
        if code == 1 and present:
            self.api.deleteParam("/test", namespace)

    def stop(self):
        if self.proc.poll() is None:
            os.kill(self.proc.pid, signal.SIGTERM)
            self.proc.wait(timeout=20)
        shutil.rmtree(self.env["ROS_LOG_DIR"], ignore_errors=True)


class Node:
    """The anchordb_ros binary with private parameters (_name:=value) and remappings; stdout and stderr to a file."""

    def __init__(self, binary, env, params, remaps):
        fd, self.log_path = tempfile.mkstemp(prefix="anchordb_ros-", suffix=".log")
        self.log = os.fdopen(fd, "wb")
        args = [binary, "__name:=anchordb_ros"] + ["_%s:=%s" % kv for kv in params.items()]
        args += ["%s:=%s" % kv for kv in remaps.items()]
        self.proc = subprocess.Popen(args, env=env, stdout=self.log, stderr=subprocess.STDOUT)

    def remove_log(self):
        if os.path.exists(self.log_path):
            os.remove(self.log_path)

    def output(self):
        with open(self.log_path, "rb") as f:
            return f.read().decode(errors="replace")

    def stop(self, timeout=30):
        """SIGINT (ros::spin returns, the node closes its model and logs its counts); the exit status."""
        if self.proc.poll() is None:
            os.kill(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                os.kill(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        self.log.close()
        return self.proc.returncode


def _load(context, name):
    spec = genmsg.msg_loader.load_msg_by_type(context, name, SEARCH)
    genmsg.msg_loader.load_depends(context, spec, SEARCH)
    return spec


def message_class(name):
    context = genmsg.MsgContext.create_default()
    spec = _load(context, name)
    return genpy.dynamic.generate_dynamic(name, genmsg.compute_full_text(context, spec))[name]


def service_class(name):
    """A rospy service class (as genpy would generate) for anchordb_ros/<Name> from clients/ros/srv."""
    context = genmsg.MsgContext.create_default()
    package, short = name.split("/")
    path = os.path.join(ROS_DIR, "srv", short + ".srv")
    spec = genmsg.msg_loader.load_srv_from_file(context, path, name)
    genmsg.msg_loader.load_depends(context, spec.request, SEARCH)
    genmsg.msg_loader.load_depends(context, spec.response, SEARCH)
    request = genpy.dynamic.generate_dynamic(name + "Request", genmsg.compute_full_text(context, spec.request))
    response = genpy.dynamic.generate_dynamic(name + "Response", genmsg.compute_full_text(context, spec.response))
    return type(short, (object,), {"_type": name, "_md5sum": genmsg.compute_md5(context, spec),
                                   "_request_class": request[name + "Request"],
                                   "_response_class": response[name + "Response"]})
