#include "pbf_ros/render/GlBackend.h"

#include <stdexcept>

#include "EglBackend.h"
#include "OsMesaBackend.h"

namespace pbf {

std::vector<std::string> glBackendNames() { return {"osmesa", "egl"}; }

std::unique_ptr<GlBackend> createGlBackend(const std::string& kind) {
  if (kind == "osmesa") return std::make_unique<OsMesaBackend>();
  if (kind == "egl") return std::make_unique<EglBackend>();
  throw std::invalid_argument("unknown GL backend '" + kind +
                              "': expected \"osmesa\" or \"egl\"");
}

}  // namespace pbf
