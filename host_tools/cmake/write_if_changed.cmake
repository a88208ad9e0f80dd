# write_if_changed(FILE TEXT): writes TEXT to FILE only when FILE does not already hold it, so that a generated file
# whose content did not change keeps its time stamp and does not rebuild what depends on it. Included by the
# generation scripts run at build time (cmake -P).
function(write_if_changed file text)
  if(EXISTS "${file}")
    file(READ "${file}" previous)
    if(previous STREQUAL text)
      return()
    endif()
  endif()
  file(WRITE "${file}" "${text}")
endfunction()
