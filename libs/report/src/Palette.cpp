#include "lidarseg/report/Palette.h"

namespace lidarseg::report {

std::vector<Rgb> referenceColours(const std::vector<std::string>& names) {
  // Two references of no known kind stay apart; a third shares the first's colour.
  constexpr Rgb kOthers[] = {kOtherColour, kWheelColour};
  std::vector<Rgb> colours;
  colours.reserve(names.size());
  std::size_t others = 0;
  for (const std::string& name : names) {
    const bool truth = name.find("truth") != std::string::npos || name == "gt";
    const bool icp = name.find("icp") != std::string::npos || name.find("ICP") != std::string::npos;
    colours.push_back(truth ? kTruthColour : icp ? kIcpColour : kOthers[others++ % 2]);
  }
  return colours;
}

}  // namespace lidarseg::report
