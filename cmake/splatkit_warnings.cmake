# Warnings for splatkit's own targets only (never global flags on third-party code).
function(splatkit_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wno-unused-parameter)
endfunction()
