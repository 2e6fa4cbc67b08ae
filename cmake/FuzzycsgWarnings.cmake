# Warning and sanitizer flags shared by every fuzzycsg target.
add_library(fuzzycsg_options INTERFACE)
add_library(fuzzycsg::options ALIAS fuzzycsg_options)
target_compile_options(fuzzycsg_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wimplicit-fallthrough $<$<BOOL:${FUZZYCSG_WERROR}>:-Werror>
  # GCC 12 reports false -Wrestrict positives inside libstdc++'s std::string operator+
  # (GCC bug 105329).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
if(FUZZYCSG_SANITIZE)
  target_compile_options(fuzzycsg_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzzycsg_options INTERFACE -fsanitize=address,undefined)
endif()
# Internal invariants stay checked in Debug and sanitizer builds (FUZZYCSG_ASSERT).
target_compile_definitions(fuzzycsg_options INTERFACE
  $<$<OR:$<CONFIG:Debug>,$<BOOL:${FUZZYCSG_SANITIZE}>>:FUZZYCSG_ENABLE_ASSERTS=1>)
