# Writes a stamp naming which of the dashboard's web files exist, with their sizes and times, and rewrites it only
# when that changes. Run at every build (a custom target): the embedding step depends on the stamp, so uPlot
# appearing after configuration (`npm ci` run after `cmake`) or changing re-embeds the page without a reconfigure.
# Run as: cmake -DSTAMP=file -DFILES=a!b!... -P dashboard_assets_stamp.cmake
cmake_minimum_required(VERSION 3.25)
include(${CMAKE_CURRENT_LIST_DIR}/write_if_changed.cmake)

string(REPLACE "!" ";" file_list "${FILES}")
set(text "")
foreach(file IN LISTS file_list)
  if(EXISTS "${file}")
    file(SIZE "${file}" size)
    file(TIMESTAMP "${file}" time "%Y-%m-%dT%H:%M:%S" UTC)
    string(APPEND text "${file} ${size} ${time}\n")
  else()
    string(APPEND text "${file} missing\n")
  endif()
endforeach()

write_if_changed("${STAMP}" "${text}")
