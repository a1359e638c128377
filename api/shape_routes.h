#pragma once
// Routes of 3D shape models (SPEC §5): training as a job (multipart spec + cloud / mesh parts), reports,
// verification (:classify) and detection (:detect) of PCD / PLY bodies.
#include "api/router.h"
#include "services/shapes/shape_service.h"

namespace anchordb::api {

void RegisterShapeRoutes(Router& router, services::ShapeService& s);

}  // namespace anchordb::api
