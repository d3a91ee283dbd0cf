#include "lidarseg/mrpt/ExceptionMessage.h"

#include <algorithm>

namespace lidarseg::mrpt_adapter {

std::string exceptionMessage(const std::string& what) {
  std::string message = what;
  const auto m = what.rfind("Message:");
  if (m != std::string::npos) message = what.substr(m + 8);
  const auto first = message.find_first_not_of(" \t\n");
  message = first == std::string::npos ? std::string() : message.substr(first);
  message = message.substr(0, message.find('\n'));
  // MRPT's banner alone on the first line (THROW_EXCEPTION's text, no "Message:"): the line
  // after it is the reason ("==== MRPT exception ====\ncannot write 'F': No space left...").
  if (message.find("MRPT exception") != std::string::npos) message.clear();
  if (message.empty()) {
    // No text after "Message:", or only the banner: the first line that is neither blank
    // nor MRPT's banner.
    std::size_t at = 0;
    while (at < what.size()) {
      const std::size_t end = std::min(what.find('\n', at), what.size());
      const std::string line = what.substr(at, end - at);
      if (line.find_first_not_of(" \t\r") != std::string::npos && line.find("MRPT exception") == std::string::npos &&
          line.find("Message:") == std::string::npos) {
        return line.substr(line.find_first_not_of(" \t\r"));
      }
      at = end + 1;
    }
    message = "unknown error";
  }
  return message;
}

}  // namespace lidarseg::mrpt_adapter
