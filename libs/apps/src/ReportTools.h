#pragma once
// Private to lidarseg::apps: what the tools measuring a log or a video share to write their
// reports (lidarseg-features, lidarseg-people): the output set, progress, timing, JSON and
// number formatting of lidarseg::pipeline and the PNG encoder of lidarseg::vision, named in
// lidarseg::apps once.

#include "lidarseg/pipeline/Format.h"
#include "lidarseg/pipeline/JsonText.h"
#include "lidarseg/pipeline/OutputFiles.h"
#include "lidarseg/pipeline/Progress.h"
#include "lidarseg/pipeline/Timing.h"
#include "lidarseg/vision/ImageFile.h"

namespace lidarseg::apps {

using pipeline::Clock;
using pipeline::finiteOrNull;
using pipeline::fixed;
using pipeline::Json;
using pipeline::jsonText;
using pipeline::microsecondsSince;
using pipeline::OutputSet;
using pipeline::Progress;
using vision::encodePng;

}  // namespace lidarseg::apps
