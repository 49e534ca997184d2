// A value from the input as a message quotes it ("stiffness [1,2] is not a number").
#pragma once

#include <cstddef>
#include <string>

#include "common/typed_value.h"

namespace springbones {

/// A typed value as compact JSON text (objects in key order, integers exactly, other numbers with
/// 15 significant digits, non-finite ones named), for messages that quote a bad value: cut to at
/// most `max_chars` bytes (common/message_number.h, appendCut) without walking the rest of a large
/// value.
std::string quoteValue(const TypedValue& value, std::size_t max_chars);

}  // namespace springbones
