#include "odometry_calibration/common/arguments.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace odometry_calibration {

double parseNumberArgument(const std::string& option, const std::string& text, double minimum)
{
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || errno != 0 || end != text.c_str() + text.size() || !std::isfinite(value) ||
      value < minimum) {
    char bound[48] = "";
    if (std::isfinite(minimum))
      std::snprintf(bound, sizeof(bound), " >= %g", minimum);
    throw ArgumentError("option " + option + ": expected a number" + bound + ", got '" + text +
                        "'");
  }
  return value;
}

std::vector<std::string> splitCommaList(const std::string& text)
{
  std::vector<std::string> pieces;
  std::stringstream stream(text);
  std::string piece;
  while (std::getline(stream, piece, ','))
    pieces.push_back(piece);
  return pieces;
}

ArgumentParser& ArgumentParser::declare(const std::string& name, bool takes_value, Store store)
{
  declared_[name] = {takes_value, std::move(store)};
  return *this;
}

ArgumentParser& ArgumentParser::flag(const std::string& name, bool* target)
{
  return declare(name, false, [target](const std::string&) { *target = true; });
}

ArgumentParser& ArgumentParser::option(const std::string& name, std::string* target)
{
  return declare(name, true, [target](const std::string& value) { *target = value; });
}

ArgumentParser& ArgumentParser::repeatedOption(const std::string& name,
                                               std::vector<std::string>* target)
{
  return declare(name, true, [target](const std::string& value) { target->push_back(value); });
}

ArgumentParser& ArgumentParser::listOption(const std::string& name,
                                           std::vector<std::string>* target)
{
  return declare(name, true,
                 [target](const std::string& value) { *target = splitCommaList(value); });
}

ArgumentParser& ArgumentParser::number(const std::string& name, double* target, double minimum)
{
  return declare(name, true, [name, target, minimum](const std::string& value) {
    *target = parseNumberArgument(name, value, minimum);
  });
}

ArgumentParser& ArgumentParser::positiveNumber(const std::string& name, double* target)
{
  return declare(name, true, [name, target](const std::string& value) {
    double number = 0.0;
    try {
      number = parseNumberArgument(name, value);
    } catch (const ArgumentError&) {
    }
    if (!(number > 0.0))
      throw ArgumentError("option " + name + ": expected a number > 0, got '" + value + "'");
    *target = number;
  });
}

ArgumentParser& ArgumentParser::wholeNumber(const std::string& name, long long* target,
                                            long long minimum, long long maximum)
{
  return declare(name, true, [name, target, minimum, maximum](const std::string& value) {
    errno = 0;
    char* end = nullptr;
    const double n = std::strtod(value.c_str(), &end);
    if (value.empty() || errno != 0 || end != value.c_str() + value.size() || !std::isfinite(n) ||
        n != std::floor(n) || n < static_cast<double>(minimum) ||
        n > static_cast<double>(maximum)) {
      const std::string range =
          maximum == std::numeric_limits<long long>::max()
              ? " >= " + std::to_string(minimum)
              : " in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
      throw ArgumentError("option " + name + ": expected a whole number" + range + ", got '" +
                          value + "'");
    }
    *target = static_cast<long long>(n);
  });
}

ArgumentParser& ArgumentParser::numberList(const std::string& name, std::vector<double>* target,
                                           std::size_t count)
{
  return declare(name, true, [name, target, count](const std::string& value) {
    std::vector<double> numbers;
    for (const std::string& piece : splitCommaList(value))
      numbers.push_back(parseNumberArgument(name, piece));
    if (numbers.size() != count) {
      throw ArgumentError("option " + name + ": expected " + std::to_string(count) +
                          " comma-separated numbers, got '" + value + "'");
    }
    *target = numbers;
  });
}

ArgumentParser& ArgumentParser::positionals(std::vector<std::string>* target, std::size_t max_count)
{
  positionals_ = target;
  max_positionals_ = max_count;
  return *this;
}

bool ArgumentParser::parse(int argc, const char* const* argv) const
{
  return parse(std::vector<std::string>(argv + (argc > 0 ? 1 : 0), argv + argc));
}

bool ArgumentParser::parse(const std::vector<std::string>& arguments) const
{
  std::size_t positional_count = 0;
  bool options_ended = false;
  for (std::size_t i = 0; i < arguments.size(); ++i) {
    const std::string& argument = arguments[i];
    const bool is_option = !options_ended && argument.size() > 1 && argument[0] == '-';
    if (!is_option) {
      if (positionals_ == nullptr || positional_count >= max_positionals_)
        throw ArgumentError("unexpected argument '" + argument + "'");
      positionals_->push_back(argument);
      ++positional_count;
    } else if (argument == "--") {
      options_ended = true;
    } else if (argument == "-h" || argument == "--help") {
      return false;
    } else {
      const auto found = declared_.find(argument);
      if (found == declared_.end())
        throw ArgumentError("unknown option '" + argument + "'");
      const Declared& declared = found->second;
      if (!declared.takes_value) {
        declared.store("");
      } else {
        if (i + 1 >= arguments.size())
          throw ArgumentError("option " + argument + " needs a value");
        declared.store(arguments[++i]);
      }
    }
  }
  return true;
}

}  // namespace odometry_calibration
