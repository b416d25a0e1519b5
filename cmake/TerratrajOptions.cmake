# Compiler options shared by every terratraj target.
# terratraj_configure_target(<target>): warnings (errors with TERRATRAJ_WERROR) and sanitizers.
function(terratraj_configure_target target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                                           -Wnon-virtual-dtor)
  if(TERRATRAJ_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

if(TERRATRAJ_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
