# EARSHOT_SANITIZE=address,undefined or thread: applied to every target in the tree.
if(EARSHOT_SANITIZE)
  message(STATUS "earshot: sanitizers ${EARSHOT_SANITIZE}")
  add_compile_options(-fsanitize=${EARSHOT_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${EARSHOT_SANITIZE})
endif()
