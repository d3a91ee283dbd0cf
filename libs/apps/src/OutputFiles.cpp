#include "OutputFiles.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace lidarseg::apps {

namespace {
void writeTemporary(const std::string& tmp, const std::string& content) {
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write '" + tmp + "'");
  out << content;
  out.flush();
  if (!out) {
    out.close();
    std::remove(tmp.c_str());
    throw std::runtime_error("error while writing '" + tmp + "'");
  }
}
}  // namespace

void writeFileAtomically(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  writeTemporary(tmp, content);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "'");
  }
}

void OutputSet::add(const std::string& path, std::string content) {
  pending_.push_back(path);  // registered first: removed on failure
  writeTemporary(path + ".tmp", content);
}

void OutputSet::addWritten(const std::string& path) { pending_.push_back(path); }

void OutputSet::commit() {
  for (const auto& path : pending_) {
    const std::string tmp = path + ".tmp";
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
      throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "'");
    }
  }
  committed_ = true;
}

OutputSet::~OutputSet() {
  if (committed_) return;
  for (const auto& path : pending_) std::remove((path + ".tmp").c_str());
}

}  // namespace lidarseg::apps
