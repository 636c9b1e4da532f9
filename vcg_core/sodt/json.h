// SPDX-License-Identifier: GPL-3.0-or-later
// A small streaming JSON writer for the CLI's reports: objects one member per
// line, arrays on one line, doubles that read back exactly, non-finite as null.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace sodt {

/// Builds one JSON document in memory. Calls must nest correctly (a key
/// before every value inside an object); misuse throws std::logic_error.
class JsonWriter {
 public:
  /// Starts an object (as a value: after key() or inside an array, or at the top).
  JsonWriter& beginObject() { return open('{', false); }
  /// Ends the innermost object.
  JsonWriter& endObject() { return close('}', false); }
  /// Starts an array; its elements are written on one line.
  JsonWriter& beginArray() { return open('[', true); }
  /// Ends the innermost array.
  JsonWriter& endArray() { return close(']', true); }

  /// Writes the key of the next object member.
  JsonWriter& key(const std::string& k) {
    if (stack_.empty() || stack_.back().array || keyPending_) throw std::logic_error("JsonWriter: misplaced key");
    separator();
    appendString(k);
    out_ += ": ";
    keyPending_ = true;
    return *this;
  }

  /// A number with the fewest digits that read back to the same double; null when not finite.
  JsonWriter& value(double x) {
    beforeValue();
    out_ += formatDouble(x);
    return *this;
  }
  JsonWriter& value(long long x) {
    beforeValue();
    out_ += std::to_string(x);
    return *this;
  }
  JsonWriter& value(int x) { return value(static_cast<long long>(x)); }
  JsonWriter& value(bool b) {
    beforeValue();
    out_ += b ? "true" : "false";
    return *this;
  }
  JsonWriter& value(const std::string& s) {
    beforeValue();
    appendString(s);
    return *this;
  }
  JsonWriter& value(const char* s) { return value(std::string(s)); }
  /// Writes null.
  JsonWriter& null() {
    beforeValue();
    out_ += "null";
    return *this;
  }

  /// Shorthand for key(k).value(v).
  template <class T>
  JsonWriter& member(const std::string& k, const T& v) {
    key(k);
    return value(v);
  }
  /// Writes key(k) and v as an array of integers.
  JsonWriter& member(const std::string& k, const std::vector<long long>& v) {
    key(k).beginArray();
    for (long long x : v) value(x);
    return endArray();
  }
  /// Writes key(k) and null.
  JsonWriter& memberNull(const std::string& k) { return key(k).null(); }

  /// The document so far, followed by a newline once it is complete.
  std::string str() const {
    if (!stack_.empty() || !done_) throw std::logic_error("JsonWriter: document is incomplete");
    return out_ + "\n";
  }

  /// Shortest "%.Ng" form of x that strtod reads back exactly; "null" when not finite.
  static std::string formatDouble(double x) {
    if (!std::isfinite(x)) return "null";
    char buf[40];
    for (int prec = 15; prec <= 17; ++prec) {
      std::snprintf(buf, sizeof buf, "%.*g", prec, x);
      if (std::strtod(buf, nullptr) == x) break;
    }
    return buf;
  }

 private:
  struct Level {
    bool array;
    int count;
  };

  JsonWriter& open(char c, bool array) {
    beforeValue();
    out_ += c;
    stack_.push_back(Level{array, 0});
    return *this;
  }

  JsonWriter& close(char c, bool array) {
    if (stack_.empty() || stack_.back().array != array || keyPending_)
      throw std::logic_error("JsonWriter: mismatched close");
    const bool empty = stack_.back().count == 0;
    stack_.pop_back();
    if (!array && !empty) newline();
    out_ += c;
    if (stack_.empty()) done_ = true;
    return *this;
  }

  void beforeValue() {
    if (stack_.empty()) {
      if (done_ || !out_.empty()) throw std::logic_error("JsonWriter: more than one top-level value");
      return;
    }
    if (!stack_.back().array) {
      if (!keyPending_) throw std::logic_error("JsonWriter: value without key in object");
      keyPending_ = false;
      return;
    }
    separator();
  }

  /// Comma and line break (objects) or space (arrays) before the next item.
  void separator() {
    Level& l = stack_.back();
    if (l.count++ > 0) out_ += l.array ? ", " : ",";
    if (!l.array) newline();
  }

  void newline() {
    out_ += '\n';
    out_.append(2 * stack_.size(), ' ');
  }

  void appendString(const std::string& s) {
    out_ += '"';
    for (unsigned char c : s) {
      switch (c) {
        case '"': out_ += "\\\""; break;
        case '\\': out_ += "\\\\"; break;
        case '\n': out_ += "\\n"; break;
        case '\r': out_ += "\\r"; break;
        case '\t': out_ += "\\t"; break;
        case '\b': out_ += "\\b"; break;
        case '\f': out_ += "\\f"; break;
        default:
          if (c < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out_ += buf;
          } else {
            out_ += static_cast<char>(c);
          }
      }
    }
    out_ += '"';
  }

  std::string out_;
  std::vector<Level> stack_;
  bool keyPending_ = false;
  bool done_ = false;
};

}  // namespace sodt
