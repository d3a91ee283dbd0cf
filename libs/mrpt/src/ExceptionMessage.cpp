#include "lidarseg/mrpt/ExceptionMessage.h"

namespace lidarseg::mrpt_adapter {

std::string exceptionMessage(const std::string& what) {
  std::string message = what;
  const auto m = what.rfind("Message:");
  if (m != std::string::npos) message = what.substr(m + 8);
  const auto first = message.find_first_not_of(" \t\n");
  message = first == std::string::npos ? std::string() : message.substr(first);
  message = message.substr(0, message.find('\n'));
  if (message.empty()) message = what.substr(0, what.find('\n'));
  return message;
}

}  // namespace lidarseg::mrpt_adapter
