// The command-line parser of the tools: a tool declares its flags, options and positionals, then
// parse() reads argv and fills the variables it was given. Help text stays each tool's own usage
// string; parse() only says whether -h/--help was asked for.
//
//   std::string config;
//   std::vector<std::string> bags;
//   double start_s = 0.0;
//   bool quiet = false;
//   ArgumentParser parser;
//   parser.option("--config", &config).number("--start", &start_s, 0.0).flag("--quiet", &quiet);
//   parser.positionals(&bags);
//   if (!parser.parse(argc, argv)) { std::cout << kUsage; return 0; }  // -h or --help
//
// Rules: arguments are read left to right; an argument starting with '-' (other than "-" itself)
// is a flag or an option, anything else a positional; an option takes the next argument as its
// value, even one that starts with '-'; "--" ends the options (all that follows is positional);
// a later value of a single-valued option replaces the earlier one. -h/--help stops the parse
// (errors in arguments before it are still reported). Every mistake throws ArgumentError with a
// message naming the option or argument, which the tools print as "error: <message>" followed by
// their usage, exiting with 2.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace odometry_calibration {

/// Wrong command-line usage; the message says what was wrong (and names the option).
class ArgumentError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// The whole of `text` as a finite number >= `minimum`; otherwise ArgumentError (a
/// std::invalid_argument) "option <option>: expected a number [>= minimum], got '<text>'".
double parseNumberArgument(const std::string& option, const std::string& text,
                           double minimum = -std::numeric_limits<double>::infinity());

/// `text` split at commas, as std::getline splits it: "" gives no piece, a trailing comma adds
/// none ("a,b," is {"a", "b"}), an inner empty piece is kept ("a,,b" is {"a", "", "b"}).
std::vector<std::string> splitCommaList(const std::string& text);

/// Declares a tool's arguments, then parses argv into the variables it was given. The
/// declaring calls return the parser, so that they can be chained. Variables keep their value
/// (the tool's default) unless the argument is given. Names are complete ("--output", "-o").
class ArgumentParser
{
public:
  /// `name` without a value: sets *target to true.
  ArgumentParser& flag(const std::string& name, bool* target);

  /// `name VALUE`: *target = VALUE.
  ArgumentParser& option(const std::string& name, std::string* target);

  /// `name VALUE`, repeatable: each VALUE is appended to *target.
  ArgumentParser& repeatedOption(const std::string& name, std::vector<std::string>* target);

  /// `name A,B,...`: *target = the comma-separated values (splitCommaList), replacing the
  /// default.
  ArgumentParser& listOption(const std::string& name, std::vector<std::string>* target);

  /// `name X`: a finite number >= minimum (parseNumberArgument's rule and message).
  ArgumentParser& number(const std::string& name, double* target,
                         double minimum = -std::numeric_limits<double>::infinity());

  /// `name X`: a finite number > 0; otherwise "option <name>: expected a number > 0, got
  /// '<text>'".
  ArgumentParser& positiveNumber(const std::string& name, double* target);

  /// `name N`: a whole number in [minimum, maximum] (written as any number: "1e3" is 1000);
  /// otherwise "option <name>: expected a
  /// whole number in [minimum, maximum], got '<text>'" (">= minimum" without a maximum).
  ArgumentParser& wholeNumber(const std::string& name, long long* target, long long minimum,
                              long long maximum = std::numeric_limits<long long>::max());

  /// `name X1,X2,...`: exactly `count` comma-separated finite numbers; otherwise "option <name>:
  /// expected <count> comma-separated numbers, got '<text>'" (or parseNumberArgument's message
  /// for a piece that is not a number).
  ArgumentParser& numberList(const std::string& name, std::vector<double>* target,
                             std::size_t count);

  /// The arguments that are not options are appended to *target, at most `max_count` of them;
  /// one more is "unexpected argument '<text>'". Without this call every positional is
  /// unexpected.
  ArgumentParser& positionals(std::vector<std::string>* target,
                              std::size_t max_count = std::numeric_limits<std::size_t>::max());

  /// Parses argv[1..argc-1]. Returns false if -h or --help was given (print the usage, exit 0),
  /// true otherwise. Throws ArgumentError: "unknown option '<arg>'", "option <name> needs a
  /// value", a value's error (see above), "unexpected argument '<arg>'".
  bool parse(int argc, const char* const* argv) const;

  /// The same for arguments without the program name.
  bool parse(const std::vector<std::string>& arguments) const;

private:
  /// Stores one value of a declared option; throws ArgumentError for a bad value.
  using Store = std::function<void(const std::string& value)>;
  ArgumentParser& declare(const std::string& name, bool takes_value, Store store);

  struct Declared
  {
    bool takes_value = true;
    Store store;
  };
  std::map<std::string, Declared> declared_;
  std::vector<std::string>* positionals_ = nullptr;
  std::size_t max_positionals_ = 0;
};

}  // namespace odometry_calibration
