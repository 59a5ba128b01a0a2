// The FCL managers behind the Broadphase interface. The only file that includes FCL.
#include <fcl/broadphase/broadphase_SaP.h>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision_object.h>

#include <chrono>
#include <cmath>

#include "tetcontact/broadphase/broadphase.hpp"

namespace tc {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A collision object whose world box is set exactly (FCL would rebuild it from a shape and a
// transform, rounding it). The box is enlarged outward by 4 ulps of its largest coordinate, so
// FCL can only report more pairs than exist; the exact test filters them.
class BoxObject : public fcl::CollisionObject<double> {
 public:
  explicit BoxObject(const std::shared_ptr<fcl::CollisionGeometry<double>>& g)
      : fcl::CollisionObject<double>(g) {}
  void set_box(const Box& b) {
    const double scale = std::max(b.lo.cwiseAbs().maxCoeff(), b.hi.cwiseAbs().maxCoeff());
    const double pad = 4.0 * std::numeric_limits<double>::epsilon() * scale + 1e-300;
    aabb = fcl::AABB<double>(fcl::Vector3d(b.lo.x() - pad, b.lo.y() - pad, b.lo.z() - pad),
                             fcl::Vector3d(b.hi.x() + pad, b.hi.y() + pad, b.hi.z() + pad));
  }
};

// Kinds of primitive, encoded with the index in the user data.
enum Kind : std::intptr_t { k_node = 0, k_face = 1, k_edge = 2 };
void* tag(Kind kind, Index i) {
  return reinterpret_cast<void*>((static_cast<std::intptr_t>(i) << 2) | kind);
}
Kind kind_of(const fcl::CollisionObject<double>* o) {
  return static_cast<Kind>(reinterpret_cast<std::intptr_t>(o->getUserData()) & 3);
}
Index index_of(const fcl::CollisionObject<double>* o) {
  return static_cast<Index>(reinterpret_cast<std::intptr_t>(o->getUserData()) >> 2);
}

struct CallbackData {
  const BroadphaseInput* in;
  Candidates* out;
};

bool collect(fcl::CollisionObject<double>* o1, fcl::CollisionObject<double>* o2, void* cdata) {
  auto* d = static_cast<CallbackData*>(cdata);
  const BroadphaseInput& in = *d->in;
  Kind k1 = kind_of(o1), k2 = kind_of(o2);
  Index i1 = index_of(o1), i2 = index_of(o2);
  if (k1 == k_edge && k2 == k_edge) {
    if (admissible_edge_edge(in, i1, i2) && boxes_overlap(in.edge_box[i1], in.edge_box[i2]))
      d->out->edge_edge.emplace_back(std::min(i1, i2), std::max(i1, i2));
    return false;
  }
  if (k1 == k_face) std::swap(k1, k2), std::swap(i1, i2);
  if (k1 == k_node && k2 == k_face && admissible_node_face(in, i1, i2) &&
      boxes_overlap(in.node_box[i1], in.face_box[i2]))
    d->out->node_face.emplace_back(i1, i2);
  return false;  // never stop early
}

class FclBroadphase : public Broadphase {
 public:
  explicit FclBroadphase(bool tree)
      : tree_(tree), shape_(std::make_shared<fcl::Sphere<double>>(1.0)) {}
  std::string name() const override { return tree_ ? "fcl_tree" : "fcl_sap"; }

  Candidates find(const BroadphaseInput& in) override {
    auto t0 = Clock::now();
    sync(nodes_, in.node_box, k_node, node_mgr_);
    sync(faces_, in.face_box, k_face, face_mgr_);
    sync(edges_, in.edge_box, k_edge, edge_mgr_);
    build_seconds = since(t0);
    t0 = Clock::now();
    Candidates c;
    CallbackData data{&in, &c};
    if (!nodes_.empty() && !faces_.empty()) node_mgr_->collide(face_mgr_.get(), &data, collect);
    if (edges_.size() > 1) edge_mgr_->collide(&data, collect);
    query_seconds = since(t0);
    std::sort(c.node_face.begin(), c.node_face.end());
    c.node_face.erase(std::unique(c.node_face.begin(), c.node_face.end()), c.node_face.end());
    std::sort(c.edge_edge.begin(), c.edge_edge.end());
    c.edge_edge.erase(std::unique(c.edge_edge.begin(), c.edge_edge.end()), c.edge_edge.end());
    return c;
  }

 private:
  using Manager = fcl::BroadPhaseCollisionManager<double>;
  std::unique_ptr<Manager> make_manager() const {
    if (tree_) return std::make_unique<fcl::DynamicAABBTreeCollisionManager<double>>();
    return std::make_unique<fcl::SaPCollisionManager<double>>();
  }

  // Same primitives as last time: set the boxes and update (refit) the tree. Otherwise, and
  // always for sweep-and-prune, rebuild: FCL 0.7's SaPCollisionManager::update() crashes
  // (a segmentation fault in updateVelist, reproduced by the broadphase tests).
  void sync(std::vector<std::unique_ptr<BoxObject>>& objs, const std::vector<Box>& boxes, Kind kind,
            std::unique_ptr<Manager>& mgr) {
    if (tree_ && mgr && objs.size() == boxes.size()) {
      for (std::size_t i = 0; i < boxes.size(); ++i) objs[i]->set_box(boxes[i]);
      mgr->update();
      return;
    }
    mgr = make_manager();
    objs.clear();
    std::vector<fcl::CollisionObject<double>*> raw;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      objs.push_back(std::make_unique<BoxObject>(shape_));
      objs.back()->set_box(boxes[i]);
      objs.back()->setUserData(tag(kind, static_cast<Index>(i)));
      raw.push_back(objs.back().get());
    }
    mgr->registerObjects(raw);
    mgr->setup();
  }

  bool tree_;
  std::shared_ptr<fcl::CollisionGeometry<double>> shape_;
  std::vector<std::unique_ptr<BoxObject>> nodes_, faces_, edges_;
  std::unique_ptr<Manager> node_mgr_, face_mgr_, edge_mgr_;
};

}  // namespace

std::unique_ptr<Broadphase> make_fcl_broadphase(bool tree) {
  return std::make_unique<FclBroadphase>(tree);
}

}  // namespace tc
