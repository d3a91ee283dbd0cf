#pragma once
// Private to lidarseg::apps: a minimal JSON writer for summaries (objects, arrays,
// numbers, strings, booleans); non-finite numbers are written as null.

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace lidarseg::apps {

class JsonWriter {
 public:
  JsonWriter& beginObject(const char* key = nullptr) { return open(key, '{'); }
  JsonWriter& endObject() { return close('}'); }
  JsonWriter& beginArray(const char* key = nullptr) { return open(key, '['); }
  JsonWriter& endArray() { return close(']'); }
  JsonWriter& value(const char* key, double v) {
    prefix(key);
    if (std::isfinite(v)) {
      std::ostringstream s;
      s << std::setprecision(10) << v;
      os_ << s.str();
    } else {
      os_ << "null";
    }
    return *this;
  }
  JsonWriter& value(const char* key, std::size_t v) {
    prefix(key);
    os_ << v;
    return *this;
  }
  JsonWriter& value(const char* key, bool v) {
    prefix(key);
    os_ << (v ? "true" : "false");
    return *this;
  }
  JsonWriter& value(const char* key, const std::string& v) {
    prefix(key);
    os_ << quote(v);
    return *this;
  }
  JsonWriter& value(const char* key, const char* v) { return value(key, std::string(v)); }
  std::string str() const { return os_.str() + "\n"; }

  static std::string quote(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
      switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        case '\r': out += "\\r"; break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
          } else {
            out += c;
          }
      }
    }
    return out + "\"";
  }

 private:
  JsonWriter& open(const char* key, char c) {
    prefix(key);
    os_ << c;
    first_.push_back(true);
    return *this;
  }
  JsonWriter& close(char c) {
    first_.pop_back();
    os_ << '\n' << std::string(2 * first_.size(), ' ') << c;
    return *this;
  }
  void prefix(const char* key) {
    if (!first_.empty()) {
      if (!first_.back()) os_ << ',';
      first_.back() = false;
      os_ << '\n' << std::string(2 * first_.size(), ' ');
    }
    if (key != nullptr) os_ << quote(key) << ": ";
  }
  std::ostringstream os_;
  std::vector<bool> first_;
};

}  // namespace lidarseg::apps
