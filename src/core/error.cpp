#include "fuzzycsg/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace fuzzycsg {

void assertion_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "fuzzycsg: internal error: assertion '%s' failed at %s:%d\n", expr, file,
               line);
  std::abort();
}

}  // namespace fuzzycsg
