#include "services/shapes/shape_settings.h"

namespace anchordb::services {

void BindShapeSettings(SettingsBinder& b, ShapeSettings& s) {
  b.Bind("shapes_max_points", "most points of one cloud given to the shape models (a training part or a query); more is "
         "refused (413)", &s.max_points, 1, 1e9);
  b.Bind("shapes_max_samples", "most training parts in one shape model training request; more is refused (413)",
         &s.max_samples, 1, 1e7);
}

}  // namespace anchordb::services
