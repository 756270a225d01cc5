// SPDX-License-Identifier: MIT
// The one list of models: adding a model = its folder + one line here.
#include "models/corotational_fem/corotational_fem.h"
#include "models/mass_spring/mass_spring.h"
#include "models/model_registry.h"
#include "models/neo_hookean/neo_hookean.h"
#include "models/projective_dynamics/projective_dynamics.h"
#include "models/shape_matching/shape_matching.h"
#include "models/xpbd/xpbd.h"
#if SOFTBENCH_WITH_BULLET
#include "models/bullet/bullet_soft_body.h"
#endif

namespace softbench {
namespace {

ModelRegistry make_builtin_registry() {
  ModelRegistry registry;
  registry.add(corotational_fem_info());
  registry.add(mass_spring_info());
  registry.add(neo_hookean_info());
  registry.add(projective_dynamics_info());
  registry.add(shape_matching_info());
  registry.add(xpbd_info());
#if SOFTBENCH_WITH_BULLET
  registry.add(bullet_deformable_info());
  registry.add(bullet_softbody_info());
#else
  for (const char* name : {"bullet_deformable", "bullet_softbody"}) {
    registry.add_unavailable(name, "configured with SOFTBENCH_WITH_BULLET=OFF");
  }
#endif
  return registry;
}

}  // namespace

const ModelRegistry& builtin_models() {
  static const ModelRegistry registry = make_builtin_registry();
  return registry;
}

}  // namespace softbench
