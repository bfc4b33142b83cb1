#include "coupling/world.hpp"

namespace dexcloth::coupling {

WorldData make_data(const WorldModel& model) {
  WorldData data;
  data.cloths.reserve(model.cloths.size());
  for (const ClothBody& body : model.cloths)
    data.cloths.push_back(cloth::make_state(body.model, body.x_rest));
  return data;
}

bool state_is_finite(const WorldData& data) {
  for (const cloth::ClothState& s : data.cloths)
    if (!s.x.allFinite() || !s.v.allFinite()) return false;
  return true;
}

}  // namespace dexcloth::coupling
