#include "passes/pass_parameters.h"

namespace penumbra {

std::string joinedNames(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names)
        text += (text.empty() ? "" : ", ") + name;
    return text;
}

ScriptError ParameterReader::atKey(const std::string& prefix, const UsageError& e) const {
    const std::string message = e.what();
    const size_t colon = message.find(": ");
    if (message.rfind(prefix, 0) != 0 || colon == std::string::npos)
        return table_.error("", message);
    return table_.error(message.substr(prefix.size(), colon - prefix.size()),
                        message.substr(colon + 2));
}

}  // namespace penumbra
