# Warning and sanitizer flags shared by every fuzzycsg target.
add_library(fuzzycsg_options INTERFACE)
add_library(fuzzycsg::options ALIAS fuzzycsg_options)
target_compile_options(fuzzycsg_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wimplicit-fallthrough $<$<BOOL:${FUZZYCSG_WERROR}>:-Werror>
  # GCC 12 reports false -Wrestrict positives inside libstdc++'s std::string operator+
  # (GCC bug 105329).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
# What a program linking the instrumented libraries needs (also given to the installed libraries'
# users, cmake/FuzzycsgModules.cmake).
set(FUZZYCSG_SANITIZER_LINK_OPTIONS "")
if(FUZZYCSG_SANITIZE OR FUZZYCSG_BUILD_FUZZ)
  set(FUZZYCSG_SANITIZER_LINK_OPTIONS -fsanitize=address,undefined)
endif()
if(FUZZYCSG_SANITIZE)
  target_compile_options(fuzzycsg_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzzycsg_options INTERFACE ${FUZZYCSG_SANITIZER_LINK_OPTIONS})
endif()
# The fuzz configuration (clang): every library is instrumented for libFuzzer's coverage and
# built with ASan and UBSan; the fuzz targets themselves add -fsanitize=fuzzer (fuzz/).
if(FUZZYCSG_BUILD_FUZZ)
  target_compile_options(fuzzycsg_options INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
    -fno-omit-frame-pointer)
  target_link_options(fuzzycsg_options INTERFACE ${FUZZYCSG_SANITIZER_LINK_OPTIONS})
endif()
# Internal invariants stay checked in Debug, sanitizer and fuzz builds (FUZZYCSG_ASSERT).
target_compile_definitions(fuzzycsg_options INTERFACE
  $<$<OR:$<CONFIG:Debug>,$<BOOL:${FUZZYCSG_SANITIZE}>,$<BOOL:${FUZZYCSG_BUILD_FUZZ}>>:FUZZYCSG_ENABLE_ASSERTS=1>)
