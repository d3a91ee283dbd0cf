#include "lidarseg/core/SensorNoise.h"

#include "Validation.h"

namespace lidarseg {

void SensorNoise::validate() const {
  detail::requireNonNegative("range_sigma_m", range_sigma_m);
  detail::requireNonNegative("bearing_sigma_rad", bearing_sigma_rad);
}

}  // namespace lidarseg
