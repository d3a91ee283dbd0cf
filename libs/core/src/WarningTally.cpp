#include "lidarseg/core/WarningTally.h"

#include <cctype>

namespace lidarseg {

namespace {
// A kind's name is cut here: a message quoting a long value stays one bounded kind name.
constexpr std::size_t kMaxKindChars = 120;
}  // namespace

std::string WarningTally::kindOf(const std::string& message) {
  const std::size_t place = message.find(": ");
  const std::size_t start = place == std::string::npos ? 0 : place + 2;
  std::string kind;
  bool in_number = false;
  for (std::size_t i = start; i < message.size() && kind.size() < kMaxKindChars; ++i) {
    const auto is_digit = [&](std::size_t j) {
      return j < message.size() && std::isdigit(static_cast<unsigned char>(message[j])) != 0;
    };
    // A sign before a number is the number's: "-0.5 rad" and "0.5 rad" are one kind.
    const bool digit = is_digit(i) || ((message[i] == '-' || message[i] == '+') && is_digit(i + 1));
    if (digit && !in_number) kind += '#';
    if (!digit) kind += message[i];
    in_number = digit;
  }
  // Never cut inside a UTF-8 character (the JSON writers refuse an invalid sequence).
  if (kind.size() >= kMaxKindChars) {
    std::size_t end = kind.size();
    while (end > 0 && (static_cast<unsigned char>(kind[end - 1]) & 0xC0) == 0x80) --end;
    if (end > 0 && (static_cast<unsigned char>(kind[end - 1]) & 0x80) != 0) {
      // kind[end - 1] leads a sequence: keep it only when all its continuation bytes are there.
      const unsigned char lead = static_cast<unsigned char>(kind[end - 1]);
      const std::size_t length = lead >= 0xF0 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC0 ? 2 : 1;
      if (kind.size() - (end - 1) < length) kind.resize(end - 1);
    }
  }
  return kind;
}

WarningTally::Kind& WarningTally::slot(const std::string& kind) {
  const auto it = index_.find(kind);
  if (it != index_.end()) return kinds_[it->second];
  if (kinds_.size() >= kMaxKinds) return other_;
  index_.emplace(kind, kinds_.size());
  kinds_.push_back(Kind{kind, 0, {}});
  return kinds_.back();
}

void WarningTally::add(const std::string& message) {
  Kind& k = slot(kindOf(message));
  if (k.count == 0) k.first = message;
  ++k.count;
  ++total_;
  if (messages_.size() < kKeptMessages) messages_.push_back(message);
}

void WarningTally::count(const std::string& kind, std::size_t n, const std::string& first) {
  if (n == 0) return;
  Kind& k = slot(kind);
  if (k.first.empty()) k.first = first;
  k.count += n;
  total_ += n;
}

void WarningTally::merge(const WarningTally& other) {
  for (const Kind& k : other.kinds()) {
    if (k.kind == kOtherKinds) {
      if (other_.first.empty()) other_.first = k.first;
      other_.count += k.count;
      total_ += k.count;
    } else {
      count(k.kind, k.count, k.first);
    }
  }
  for (const std::string& m : other.messages_) {
    if (messages_.size() < kKeptMessages) messages_.push_back(m);
  }
}

std::vector<WarningTally::Kind> WarningTally::kinds() const {
  std::vector<Kind> out = kinds_;
  if (other_.count > 0) out.push_back(other_);
  return out;
}

std::size_t WarningTally::countOf(const std::string& kind) const {
  if (kind == kOtherKinds) return other_.count;
  const auto it = index_.find(kind);
  return it == index_.end() ? 0 : kinds_[it->second].count;
}

}  // namespace lidarseg
