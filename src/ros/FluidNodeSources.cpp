// Fluid that enters and leaves the running simulation: the scene's emitters and drains after
// every step, and the ~emit service. All of it runs on the simulation thread between steps
// (pbf::FluidSources does the work and keeps the books that ~stats reports).
#include <cmath>
#include <sstream>

#include "pbf_ros/ros/EchoedText.h"
#include "pbf_ros/ros/FluidNode.h"
#include "pbf_ros/ros/WallThrottle.h"

namespace pbf_ros {

namespace {

// A frame publisher started beside the node needs a moment: no warning before this [wall s].
constexpr double kEmitterFrameGrace = 3.0;

// A request's double as the solver's float: finite both ways (1e39 is a finite double but
// an infinite float), or the name of the field that is not. Messages print a double whole
// (17 digits): a radius of 5e-324 read "got 0".
bool toFloat(double value, float& out) {
  out = static_cast<float>(value);
  return std::isfinite(value) && std::isfinite(out);
}

// The request as a FluidBlock, or what is wrong with it (naming the field).
std::string blockFromRequest(const Emit::Request& req, pbf::FluidBlock& block) {
  auto vec = [](const char* name, double x, double y, double z, Eigen::Vector3f& out) -> std::string {
    if (toFloat(x, out.x()) && toFloat(y, out.y()) && toFloat(z, out.z())) return "";
    std::ostringstream m;
    m.precision(17);
    m << "field '" << name << "': expected numbers a float holds (finite, |x| < 3.4e38), got [" << x
      << ", " << y << ", " << z << "]";
    return m.str();
  };
  std::string err = vec("velocity", req.velocity.x, req.velocity.y, req.velocity.z, block.velocity);
  if (!err.empty()) return err;
  if (req.shape == "box") {
    block.shape = pbf::FluidBlock::Shape::Box;
    err = vec("min", req.min.x, req.min.y, req.min.z, block.min);
    if (err.empty()) err = vec("max", req.max.x, req.max.y, req.max.z, block.max);
  } else if (req.shape == "sphere") {
    block.shape = pbf::FluidBlock::Shape::Sphere;
    err = vec("center", req.center.x, req.center.y, req.center.z, block.center);
    if (err.empty() && !toFloat(req.radius, block.radius)) {
      std::ostringstream m;
      m.precision(17);
      m << "field 'radius': expected a number > 0 [m] a float holds (|r| < 3.4e38), got " << req.radius;
      err = m.str();
    }
  } else {
    return "field 'shape': expected \"box\" or \"sphere\", got \"" + echoed(req.shape) + "\"";
  }
  if (!err.empty()) return err;
  const std::string invalid = pbf::validateBlock(block);
  return invalid.empty() ? "" : "field '" + invalid.substr(0, invalid.find(':')) + "'" +
                                    invalid.substr(invalid.find(':'));
}

}  // namespace

void FluidNode::applySources(double dt) {
  if (sources_.emitters().empty() && sources_.drains().empty()) return;
  // Nozzles attached to tf frames go where their frame is now. One whose frame tf does not
  // know stays where it was; until its frame has been seen once it stays shut (FluidSources).
  for (std::size_t k = 0; k < sources_.emitters().size(); ++k) {
    const std::string& frame = sources_.emitters()[k].frame;
    if (frame.empty()) continue;
    if (!attachments_) attachments_ = std::make_unique<TfAttachments>(domain_frame_);
    Eigen::Isometry3f pose;
    if (attachments_->currentPose(frame, pose)) {
      sources_.setEmitterPose(k, pose);
    } else if (wallNow() - sources_since_wall_ > kEmitterFrameGrace) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: no tf for emitter %zu's frame '%s' (%s -> it); it stays "
                        "where it was (shut, if its frame was never seen)",
                        k, frame.c_str(), domain_frame_.c_str());
    }
  }
  try {
    const pbf::FluidSources::StepResult r = sources_.afterStep(*solver_, dt, max_particles_);
    for (std::size_t k : r.too_fast) {
      PBF_WARN_THROTTLE(10.0, "pbf_node: emitter %zu: %.4g m/s is more than 8 particle spacings per step "
                        "(dt %.3g s); its oldest layers were dropped (with adaptive_time_step the next "
                        "steps shorten to the jet)", k, pbf::emitterSpeed(sources_.emitters()[k],
                        solver_->params().particle_spacing), dt);
    }
    for (std::size_t k : r.held_by_limit) {
      PBF_WARN_THROTTLE(5.0, "pbf_node: emitter %zu held: its layer would bring the fluid beyond "
                        "~max_particles (%zu particles); it emits again once drains make room",
                        k, max_particles_);
    }
  } catch (const std::exception& e) {  // cannot happen with validated emitters; be sure
    PBF_ERROR_THROTTLE(5.0, "pbf_node: sources and drains skipped this step: %s", e.what());
  }
}

bool FluidNode::onEmitService(Emit::Request& req, Emit::Response& res) {
  pbf::FluidBlock block;
  const std::string invalid = blockFromRequest(req, block);
  // Shared, not a reference: after a shutdown timeout the task may still run.
  auto result = std::make_shared<Emit::Response>();
  const std::string frame = req.frame_id;
  const std::string error = runOnSimulation([this, invalid, block, frame, result]() -> std::string {
    // The count is read here, on the thread that changes it.
    result->particle_count = static_cast<std::uint32_t>(solver_->size());
    if (!invalid.empty()) return invalid;
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
    if (!frame.empty() && frame != domain_frame_) {
      if (!attachments_) attachments_ = std::make_unique<TfAttachments>(domain_frame_);
      if (!attachments_->currentPose(frame, pose))
        return "field 'frame_id': no tf from " + domain_frame_ + " to '" + echoed(frame) + "'";
    }
    try {
      const pbf::SiteCount c = sources_.emitBlock(*solver_, block, pose, max_particles_);
      result->added = static_cast<std::uint32_t>(c.added);
      result->skipped = static_cast<std::uint32_t>(c.occupied + c.in_solid + c.outside);
      result->particle_count = static_cast<std::uint32_t>(solver_->size());
      std::ostringstream m;
      m << "added " << c.added << " particles (" << c.occupied << " sites occupied by fluid, "
        << c.in_solid << " inside solids, " << c.outside << " outside the container); "
        << solver_->size() << " particles now";
      result->message = m.str();
    } catch (const std::invalid_argument& e) {
      std::string why = e.what();
      // The core names the limit; the user knows it as the node's parameter.
      const std::size_t at = why.find("max_particles");
      if (at != std::string::npos) why.insert(at, "~");
      return why;
    }
    ++state_version_;  // the cloud and the render snapshot show the new fluid
    updateHealth();
    return "";
  });
  res = *result;
  res.success = error.empty();
  if (!res.success) {
    res.added = 0;
    res.message = "~emit refused: " + error + "; the simulation is unchanged";
    ROS_WARN("pbf_node: %s", res.message.c_str());
  }
  return true;
}

}  // namespace pbf_ros
