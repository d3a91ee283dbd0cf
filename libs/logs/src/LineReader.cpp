#include "lidarseg/logs/LineReader.h"

#include <stdexcept>

#include <zlib.h>

namespace lidarseg::logs {

LineReader::LineReader(const std::string& path) : path_(path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (f == nullptr) throw std::runtime_error("cannot open '" + path + "'");
  file_ = f;
}

LineReader::~LineReader() {
  if (file_ != nullptr) gzclose(static_cast<gzFile>(file_));
}

bool LineReader::next(std::string& line) {
  line.clear();
  auto* f = static_cast<gzFile>(file_);
  char buffer[4096];
  bool any = false;
  while (true) {
    if (gzgets(f, buffer, sizeof buffer) == nullptr) {
      int code = Z_OK;
      const char* message = gzerror(f, &code);
      if (code != Z_OK && code != Z_STREAM_END) {
        throw std::runtime_error(path_ + ":" + std::to_string(line_ + 1) +
                                 ": corrupt or truncated compressed data (" +
                                 (message ? message : "zlib error") + ")");
      }
      break;  // end of file
    }
    any = true;
    line += buffer;
    if (!line.empty() && line.back() == '\n') break;
  }
  if (!any) return false;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  ++line_;
  return true;
}

}  // namespace lidarseg::logs
