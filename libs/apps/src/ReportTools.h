#pragma once
// Private to lidarseg::apps: what the tools measuring a log or a video share to write their
// reports (lidarseg-features, lidarseg-people): the output set, progress, timing, JSON and
// number formatting of lidarseg::pipeline and the PNG encoder of lidarseg::vision, named in
// lidarseg::apps once.

#include "lidarseg/report/Format.h"
#include "lidarseg/report/JsonText.h"
#include "lidarseg/report/OutputFiles.h"
#include "lidarseg/report/Progress.h"
#include "lidarseg/report/Timing.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::apps {

using report::Clock;
using report::finiteOrNull;
using report::fixed;
using report::Json;
using report::jsonText;
using report::microsecondsSince;
using report::OutputSet;
using report::Progress;
using vision::encodePng;

}  // namespace lidarseg::apps
