#include "lidarseg/core/SensorNoise.h"

#include "Validation.h"

namespace lidarseg {

void SensorNoise::validate() const {
  detail::requireSigmaM("range_sigma_m", range_sigma_m, true);
  detail::requireSigmaRad("bearing_sigma_rad", bearing_sigma_rad, true);
}

}  // namespace lidarseg
