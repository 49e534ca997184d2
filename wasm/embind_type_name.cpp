// The runtime module's siprintf, for the one printf call the module has: embind's __getTypeName
// (system/lib/embind/bind.cpp), which, with EMSCRIPTEN_HAS_UNBOUND_TYPE_NAMES=0 (wasm/CMakeLists.txt),
// names a type by its address with sprintf(buffer, "%p", type), a call clang turns into siprintf
// (printf without floating point). With this definition linked ahead of libc, libc's sprintf.o
// and printf (printf_core and its callers, 3.3 KB of code, 1.8 KB gzip) stay out of the module:
// the runtime formats no number in C++ (common/message_number.h). It writes "%p" as musl does
// ("0x" and at least 8 hex digits) and nothing else: another format is written as it is, which no
// caller in the module asks for.
#include <cstdarg>
#include <cstdint>
#include <cstring>

extern "C" int siprintf(char* out, const char* format, ...) {
  if (std::strcmp(format, "%p") != 0) {
    std::strcpy(out, format);
    return static_cast<int>(std::strlen(out));
  }
  va_list arguments;
  va_start(arguments, format);
  const auto address = reinterpret_cast<std::uintptr_t>(va_arg(arguments, const void*));
  va_end(arguments);
  int digits = 8;
  while (digits < 2 * static_cast<int>(sizeof address) && (address >> (4 * digits)) != 0) ++digits;
  char* at = out;
  *at++ = '0';
  *at++ = 'x';
  for (int i = digits - 1; i >= 0; --i) *at++ = "0123456789abcdef"[(address >> (4 * i)) & 15];
  *at = '\0';
  return static_cast<int>(at - out);
}
