// The only translation unit of the importer that includes ROS headers.
#include "server/rosbag/rosbag_source.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <ros/exception.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

namespace anchordb::server {

namespace {

std::string Bare(const std::string& frame) { return frame.rfind('/', 0) == 0 ? frame.substr(1) : frame; }

std::string Name(const std::string& bag_path) { return "bag " + bag_path; }

// Opens the bag; an unindexed (truncated) or unreadable file is a clear error, not a ROS exception.
void OpenBag(rosbag::Bag& bag, const std::string& bag_path) {
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw std::invalid_argument(Name(bag_path) + ": unindexed, probably truncated (a recording cut short; "
                                "`rosbag reindex` repairs it)");
  } catch (const rosbag::BagException& e) {
    throw std::invalid_argument(Name(bag_path) + ": cannot be read as a ROS 1 bag (truncated or damaged?): " +
                                e.what());
  }
}

std::set<std::string> TopicsOf(const rosbag::Bag& bag) {
  rosbag::View all(bag);
  std::set<std::string> topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections()) topics.insert(c->topic);
  return topics;
}

Eigen::Isometry3d IsometryOf(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return X;
}

// Every /tf and /tf_static transform of the bag in one buffer whose cache spans the whole recording.
std::int64_t FillTf(const rosbag::Bag& bag, tf2::BufferCore& tf) {
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"}));
  std::int64_t messages = 0;
  for (const rosbag::MessageInstance& m : view) {
    const tf2_msgs::TFMessage::ConstPtr msg = m.instantiate<tf2_msgs::TFMessage>();
    if (!msg) continue;
    ++messages;
    const bool is_static = m.getTopic() == "/tf_static";
    for (geometry_msgs::TransformStamped t : msg->transforms) {
      t.header.frame_id = Bare(t.header.frame_id);
      t.child_frame_id = Bare(t.child_frame_id);
      tf.setTransform(t, "bag", is_static);
    }
  }
  return messages;
}

void CheckEncoding(const std::string& encoding, const std::string& bag_path, const std::string& topic) {
  if (encoding != "16UC1" && encoding != "mono16" && encoding != "32FC1") {
    throw std::invalid_argument(Name(bag_path) + ": depth topic " + topic + " has encoding '" + encoding +
                                "'; supported: 16UC1 / mono16 (millimetres) and 32FC1 (metres)");
  }
}

// The image's rows fit its data (a message cut short or with a wrong step would be read past its end).
void CheckImageSize(const sensor_msgs::Image& image, std::size_t bytes_per_pixel, const std::string& bag_path,
                    const std::string& topic, std::int64_t index) {
  if (image.step < image.width * bytes_per_pixel ||
      image.data.size() < static_cast<std::size_t>(image.step) * image.height) {
    throw std::invalid_argument(Name(bag_path) + ": image " + std::to_string(index) + " on " + topic + " has " +
                                std::to_string(image.data.size()) + " bytes for " + std::to_string(image.height) +
                                " rows of step " + std::to_string(image.step) + " (" + std::to_string(image.width) +
                                " pixels of " + std::to_string(bytes_per_pixel) + " bytes)");
  }
}

BagCamera FirstCameraInfo(const rosbag::Bag& bag, const std::string& bag_path, const std::string& topic) {
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  for (const rosbag::MessageInstance& m : view) {
    const sensor_msgs::CameraInfo::ConstPtr info = m.instantiate<sensor_msgs::CameraInfo>();
    if (!info) throw std::invalid_argument(Name(bag_path) + ": topic " + topic + " is not sensor_msgs/CameraInfo");
    if (info->K[0] <= 0 || info->K[4] <= 0 || info->width == 0 || info->height == 0) {
      throw std::invalid_argument(Name(bag_path) + ": camera info on " + topic + " has no focal length or size");
    }
    BagCamera camera;
    camera.width = static_cast<int>(info->width), camera.height = static_cast<int>(info->height);
    camera.fx = info->K[0], camera.fy = info->K[4], camera.cx = info->K[2], camera.cy = info->K[5];
    return camera;
  }
  throw std::invalid_argument(Name(bag_path) + ": camera info topic " + topic + " holds no message");
}

}  // namespace

RosbagTopics TumPresetTopics() {
  RosbagTopics topics;
  topics.depth = "/camera/depth/image";
  topics.info = "/camera/depth/camera_info";
  topics.map_frame = "world";
  return topics;
}

BagScan ScanBag(const std::string& bag_path, const RosbagTopics& topics) {
  rosbag::Bag bag;
  OpenBag(bag, bag_path);
  BagScan scan;
  try {
    const std::set<std::string> present = TopicsOf(bag);
    for (const std::string* topic : {&topics.depth, &topics.info}) {
      if (!present.count(*topic)) throw std::invalid_argument(Name(bag_path) + ": no topic " + *topic);
    }
    if (!topics.grid.empty() && !present.count(topics.grid)) {
      throw std::invalid_argument(Name(bag_path) + ": no grid topic " + topics.grid);
    }
    if (!topics.mask.empty() && !present.count(topics.mask)) {
      throw std::invalid_argument(Name(bag_path) + ": no mask topic " + topics.mask);
    }
    scan.camera = FirstCameraInfo(bag, bag_path, topics.info);
    rosbag::View whole(bag);
    const double span_s = (whole.getEndTime() - whole.getBeginTime()).toSec();
    tf2::BufferCore tf(ros::Duration(span_s + 60.0));
    scan.tf_messages = FillTf(bag, tf);
    if (scan.tf_messages == 0) throw std::invalid_argument(Name(bag_path) + ": no tf (/tf or /tf_static) message");
    rosbag::View depth(bag, rosbag::TopicQuery(topics.depth));
    for (const rosbag::MessageInstance& m : depth) {
      const std::int64_t index = scan.depth_messages++;
      const sensor_msgs::Image::ConstPtr image = m.instantiate<sensor_msgs::Image>();
      if (!image) throw std::invalid_argument(Name(bag_path) + ": topic " + topics.depth + " is not sensor_msgs/Image");
      CheckEncoding(image->encoding, bag_path, topics.depth);
      if (scan.encoding.empty()) scan.encoding = image->encoding;
      if (static_cast<int>(image->width) != scan.camera.width || static_cast<int>(image->height) != scan.camera.height) {
        throw std::invalid_argument(Name(bag_path) + ": depth image " + std::to_string(index) + " is " +
                                    std::to_string(image->width) + " x " + std::to_string(image->height) +
                                    ", the camera info says " + std::to_string(scan.camera.width) + " x " +
                                    std::to_string(scan.camera.height));
      }
      CheckImageSize(*image, image->encoding == "32FC1" ? 4 : 2, bag_path, topics.depth, index);
      if (index % topics.every != 0) {
        ++scan.skipped_every;
        continue;
      }
      try {
        const geometry_msgs::TransformStamped X =
            tf.lookupTransform(Bare(topics.map_frame), Bare(image->header.frame_id), image->header.stamp);
        scan.frames.push_back({index, image->header.stamp.toSec(), IsometryOf(X.transform)});
      } catch (const tf2::TransformException&) {
        ++scan.skipped_no_pose;
      }
    }
    if (!topics.grid.empty()) scan.has_grid = rosbag::View(bag, rosbag::TopicQuery(topics.grid)).size() > 0;
    if (!topics.mask.empty()) {
      for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topics.mask))) {
        const sensor_msgs::Image::ConstPtr image = m.instantiate<sensor_msgs::Image>();
        if (!image) throw std::invalid_argument(Name(bag_path) + ": topic " + topics.mask + " is not sensor_msgs/Image");
        if (image->encoding != "mono8" && image->encoding != "8UC1") {
          throw std::invalid_argument(Name(bag_path) + ": mask encoding '" + image->encoding + "' on " + topics.mask +
                                      " (known: mono8, 8UC1)");
        }
        if (static_cast<int>(image->width) != scan.camera.width || static_cast<int>(image->height) != scan.camera.height) {
          throw std::invalid_argument(Name(bag_path) + ": mask " + std::to_string(scan.mask_messages) + " is " +
                                      std::to_string(image->width) + " x " + std::to_string(image->height) +
                                      ", the depth images are " + std::to_string(scan.camera.width) + " x " +
                                      std::to_string(scan.camera.height));
        }
        CheckImageSize(*image, 1, bag_path, topics.mask, scan.mask_messages);
        ++scan.mask_messages;
      }
    }
  } catch (const ros::Exception& e) {  // rosbag's exceptions, and a message cut short (StreamOverrunException)
    throw std::invalid_argument(Name(bag_path) + ": unreadable (truncated or damaged): " + e.what());
  }
  if (scan.frames.empty()) {
    throw std::invalid_argument(Name(bag_path) + ": none of the " + std::to_string(scan.depth_messages) +
                                " depth images has a pose in frame '" + topics.map_frame + "' (tf)");
  }
  return scan;
}

namespace {

std::string ToMillimetres(const sensor_msgs::Image& image) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::string out(n * 2, '\0');
  const bool big_endian = image.is_bigendian != 0;
  for (std::size_t r = 0; r < image.height; ++r) {
    const std::uint8_t* row = image.data.data() + r * image.step;
    for (std::size_t c = 0; c < image.width; ++c) {
      std::uint16_t mm = 0;
      if (image.encoding == "32FC1") {
        float m = 0;
        std::memcpy(&m, row + c * 4, 4);
        if (std::isfinite(m) && m > 0.0f) mm = static_cast<std::uint16_t>(std::min(65535.0f, std::round(m * 1000.0f)));
      } else {
        const std::uint8_t* p = row + c * 2;
        mm = big_endian ? static_cast<std::uint16_t>(p[0] << 8 | p[1]) : static_cast<std::uint16_t>(p[1] << 8 | p[0]);
      }
      const std::size_t i = (r * image.width + c) * 2;
      out[i] = static_cast<char>(mm & 0xff);
      out[i + 1] = static_cast<char>(mm >> 8);
    }
  }
  return out;
}

}  // namespace

void ReadDepthImages(const std::string& bag_path, const RosbagTopics& topics, const std::vector<std::int64_t>& wanted,
                     const std::function<void(std::int64_t index, const BagDepthPixels& pixels)>& consume) {
  rosbag::Bag bag;
  OpenBag(bag, bag_path);
  std::vector<std::string> query{topics.depth};
  if (!topics.mask.empty()) query.push_back(topics.mask);
  rosbag::View view(bag, rosbag::TopicQuery(query));
  // A mask may be recorded before or after the depth image of its stamp (messages of one time come in no fixed order
  // across topics, and a mask is often recorded a little later): a depth image waits until its mask came or the bag's
  // time is kMaskWaitS past its own, then goes on without one.
  constexpr double kMaskWaitS = 0.5;
  struct Waiting {
    std::int64_t index = 0;
    double record_s = 0.0;
    ros::Time stamp;
    BagDepthPixels pixels;
  };
  std::deque<Waiting> waiting;
  std::map<ros::Time, std::vector<std::uint8_t>> masks;  // by stamp, until their depth image came
  const auto hand_on = [&](bool all, double now_s) {
    while (!waiting.empty()) {
      Waiting& w = waiting.front();
      const auto mask = masks.find(w.stamp);
      if (mask != masks.end()) {
        w.pixels.mask = std::move(mask->second);
        masks.erase(masks.begin(), std::next(mask));  // older masks: their depth image went on already
      } else if (!all && now_s - w.record_s < kMaskWaitS) {
        return;
      }
      consume(w.index, w.pixels);
      waiting.pop_front();
    }
  };
  std::int64_t index = -1;
  std::size_t next = 0;
  for (const rosbag::MessageInstance& m : view) {
    const double now_s = m.getTime().toSec();
    hand_on(topics.mask.empty(), now_s);
    if (next == wanted.size() && waiting.empty()) break;
    const sensor_msgs::Image::ConstPtr image = m.instantiate<sensor_msgs::Image>();
    if (!image) continue;
    if (m.getTopic() != topics.depth) {
      std::vector<std::uint8_t> mask(static_cast<std::size_t>(image->width) * image->height, 0);
      for (std::size_t r = 0; r < image->height; ++r) {
        for (std::size_t c = 0; c < image->width; ++c) mask[r * image->width + c] = image->data[r * image->step + c] ? 255 : 0;
      }
      masks[image->header.stamp] = std::move(mask);
      continue;
    }
    if (next == wanted.size() || ++index != wanted[next]) continue;
    ++next;
    waiting.push_back({index, now_s, image->header.stamp, {ToMillimetres(*image), {}}});
  }
  hand_on(true, 0.0);
}

BagGrid ReadLastGrid(const std::string& bag_path, const std::string& grid_topic) {
  rosbag::Bag bag;
  OpenBag(bag, bag_path);
  BagGrid grid;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(grid_topic))) {
    const nav_msgs::OccupancyGrid::ConstPtr msg = m.instantiate<nav_msgs::OccupancyGrid>();
    if (!msg) throw std::invalid_argument(Name(bag_path) + ": topic " + grid_topic + " is not nav_msgs/OccupancyGrid");
    if (msg->data.size() != static_cast<std::size_t>(msg->info.width) * msg->info.height || msg->data.empty() ||
        !(msg->info.resolution > 0.0f)) {
      throw std::invalid_argument(Name(bag_path) + ": grid on " + grid_topic + " has " + std::to_string(msg->data.size()) +
                                  " cells for " + std::to_string(msg->info.width) + " x " +
                                  std::to_string(msg->info.height) + " at resolution " +
                                  std::to_string(msg->info.resolution));
    }
    grid.resolution_m = msg->info.resolution;
    grid.origin_x_m = msg->info.origin.position.x, grid.origin_y_m = msg->info.origin.position.y;
    const geometry_msgs::Quaternion& q = msg->info.origin.orientation;
    grid.origin_yaw_rad = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    grid.width = static_cast<int>(msg->info.width), grid.height = static_cast<int>(msg->info.height);
    grid.cells.assign(msg->data.begin(), msg->data.end());
  }
  return grid;
}

}  // namespace anchordb::server
