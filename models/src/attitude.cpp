#include "terratraj/models/attitude.hpp"

namespace terratraj::models {

const char* attitudeStatusName(AttitudeStatus status) {
  switch (status) {
    case AttitudeStatus::kOk:
      return "ok";
    case AttitudeStatus::kNoTerrain:
      return "no_terrain";
    case AttitudeStatus::kNoContact:
      return "no_contact";
  }
  return "unknown";
}

}  // namespace terratraj::models
