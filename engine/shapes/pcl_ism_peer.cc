// PCL's ISM stays inside this translation unit.
#include "engine/shapes/pcl_ism_peer.h"

#include <algorithm>
#include <cmath>

#include <pcl/console/print.h>
#include <pcl/features/fpfh.h>
#include <pcl/features/impl/fpfh.hpp>
#include <pcl/features/normal_3d.h>
#include <pcl/recognition/implicit_shape_model.h>
#include <pcl/recognition/impl/implicit_shape_model.hpp>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Normals = pcl::PointCloud<pcl::Normal>;
using Estimation = pcl::ism::ImplicitShapeModelEstimation<153, pcl::PointXYZ, pcl::Normal>;

Cloud::Ptr ToCloud(const std::vector<Eigen::Vector3f>& points_m) {
  auto cloud = std::make_shared<Cloud>();
  for (const auto& p : points_m) {
    if (p.allFinite()) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  }
  return cloud;
}

Normals::Ptr NormalsOf(const Cloud::Ptr& cloud, double radius_m) {
  auto normals = std::make_shared<Normals>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setRadiusSearch(radius_m);
  ne.compute(*normals);
  return normals;
}

// PCL 1.13's mean shift (ISMVoteList::shiftMean) divides by the summed kernel weight of the votes near its start;
// a start vote of strength 0 (a codeword whose learned statistics weight it 0) or a non-finite vote gives a NaN
// centre, and the next radius search aborts in kdtree_flann.hpp ("Invalid NaN point"). Such votes add nothing to a
// density, so the peer drops them before asking for peaks. The vote list keeps them in protected members; this
// subclass only reaches them.
struct VoteListCleaner : pcl::features::ISMVoteList<pcl::PointXYZ> {
  static std::size_t DropUselessVotes(pcl::features::ISMVoteList<pcl::PointXYZ>& list) {
    auto& l = static_cast<VoteListCleaner&>(list);
    auto votes = std::make_shared<pcl::PointCloud<pcl::InterestPoint>>();
    auto origins = std::make_shared<Cloud>();
    std::vector<int> classes;
    std::size_t dropped = 0;
    for (std::size_t i = 0; i < l.votes_->size(); ++i) {
      const pcl::InterestPoint& v = (*l.votes_)[i];
      if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.strength) && v.strength > 0) {
        votes->push_back(v);
        origins->push_back((*l.votes_origins_)[i]);
        classes.push_back(l.votes_class_[i]);
      } else {
        ++dropped;
      }
    }
    l.votes_ = votes;
    l.votes_origins_ = origins;
    l.votes_class_ = std::move(classes);
    l.tree_is_valid_ = false;
    return dropped;
  }
};

}  // namespace

struct PclIsm::Impl {
  PclIsmParams params;
  std::vector<std::string> categories;
  Estimation::ISMModelPtr model = std::make_shared<pcl::features::ISMModel>();
  mutable Estimation ism;
};

PclIsm::PclIsm(const std::vector<LabelledCloud>& samples, const PclIsmParams& params) : impl_(std::make_unique<Impl>()) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  impl_->params = params;
  std::vector<Cloud::Ptr> clouds;
  std::vector<Normals::Ptr> normals;
  std::vector<unsigned> classes;
  for (const auto& s : samples) {
    auto it = std::find(impl_->categories.begin(), impl_->categories.end(), s.category);
    if (it == impl_->categories.end()) it = impl_->categories.insert(impl_->categories.end(), s.category);
    clouds.push_back(ToCloud(s.points_m));
    normals.push_back(NormalsOf(clouds.back(), params.normal_radius_m));
    classes.push_back(static_cast<unsigned>(it - impl_->categories.begin()));
  }
  if (clouds.empty()) throw Error(ErrorCode::kInvalidArgument, "there are no training samples", "samples");
  auto fpfh = std::make_shared<pcl::FPFHEstimation<pcl::PointXYZ, pcl::Normal, pcl::Histogram<153>>>();
  fpfh->setRadiusSearch(params.fpfh_radius_m);
  impl_->ism.setFeatureEstimator(fpfh);
  impl_->ism.setTrainingClouds(clouds);
  impl_->ism.setTrainingNormals(normals);
  impl_->ism.setTrainingClasses(classes);
  impl_->ism.setSamplingSize(static_cast<float>(params.sampling_m));
  impl_->ism.setNumberOfClusters(static_cast<unsigned>(params.clusters));
  impl_->ism.trainISM(impl_->model);
}

PclIsm::~PclIsm() = default;

const std::vector<std::string>& PclIsm::categories() const { return impl_->categories; }

PclIsmResult PclIsm::Classify(const std::vector<Eigen::Vector3f>& points_m, bool by_centre) const {
  PclIsmResult out;
  const Cloud::Ptr cloud = ToCloud(points_m);
  if (cloud->empty()) return out;
  const Normals::Ptr normals = NormalsOf(cloud, impl_->params.normal_radius_m);
  Eigen::Vector4f centroid;
  pcl::compute3DCentroid(*cloud, centroid);
  pcl::PointXYZ centre(centroid.x(), centroid.y(), centroid.z());
  double best = 0;
  for (std::size_t c = 0; c < impl_->categories.size(); ++c) {
    const auto votes = impl_->ism.findObjects(impl_->model, cloud, normals, static_cast<int>(c));
    const double sigma = impl_->model->sigmas_[c];
    std::vector<pcl::ISMPeak, Eigen::aligned_allocator<pcl::ISMPeak>> peaks;
    double peak = 0, at_centre = 0;
    out.dropped_votes += VoteListCleaner::DropUselessVotes(*votes);
    if (votes->getNumberOfVotes() > 0 && std::isfinite(sigma) && sigma > 0) {
      votes->findStrongestPeaks(peaks, static_cast<int>(c), sigma * 10, sigma);
      for (const auto& p : peaks) peak = std::max(peak, static_cast<double>(p.density));
      at_centre = votes->getDensityAtPoint(centre, sigma);
    }
    out.peak_density.push_back(peak);
    out.centre_density.push_back(at_centre);
    const double score = by_centre ? at_centre : peak;
    if (score > best) {
      best = score;
      out.best = impl_->categories[c];
    }
  }
  return out;
}

}  // namespace anchordb::engine
