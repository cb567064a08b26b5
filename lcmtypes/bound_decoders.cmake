# Bounds lcm-gen's C++ decoders before they allocate (docs/bus.md, "Bounded decoding").
#
# lcm-gen (1.4) sizes an array from its count field before it reads a byte of the elements:
# `this->data.resize(this->nbytes)` with nbytes = 2^31-1 took gigabytes from a datagram of 100
# bytes, and a negative count threw std::length_error through liblcm's C frames (abort). A
# string's length of 0 or less was taken as size_t(-1). Every element takes at least one byte on
# the wire and a string at least its NUL, so a count above the bytes left, or below 0, is refused
# (decode returns -1, as for any other malformed message) before anything is allocated. A string
# must also end in its NUL and hold no other: the encoder writes strlen() bytes, so a string read
# with a NUL inside would be written back shorter than getEncodedSize() says. (scripts/fuzz found
# the first version of this file missing the strings of string arrays, `__elem_len`: an
# episode_truth_t whose oracle step had length 0 threw through the decoder.)
#
# Run as: cmake -DDIR=<folder of generated .hpp> -P bound_decoders.cmake
file(GLOB headers "${DIR}/*.hpp")
foreach(header ${headers})
  file(READ "${header}" text)
  string(REGEX MATCHALL "\\.resize\\(" resizes "${text}")
  string(REGEX MATCHALL "_len_* > maxlen - pos\\) return -1" strings "${text}")
  string(REGEX REPLACE
    "this->([A-Za-z_0-9]+)\\.resize\\(this->([A-Za-z_0-9]+)\\);"
    "if(this->\\2 < 0 || this->\\2 > maxlen - pos) return -1;  // bound_decoders.cmake\n        this->\\1.resize(this->\\2);"
    text "${text}")
  string(REGEX REPLACE
    "if\\((__[A-Za-z_0-9]+) > maxlen - pos\\) return -1;"
    "if(\\1 < 1 || \\1 > maxlen - pos || memchr(((const char*)buf) + offset + pos, 0, \\1 - 1) != nullptr || ((const char*)buf)[offset + pos + \\1 - 1] != 0) return -1;  // bound_decoders.cmake"
    text "${text}")
  # Every resize and every string must have been bounded: a change in lcm-gen's output fails
  # the build here rather than leaving a decoder unbounded.
  string(REGEX MATCHALL "bound_decoders\\.cmake" bounded "${text}")
  list(LENGTH resizes n_resizes)
  list(LENGTH strings n_strings)
  list(LENGTH bounded n_bounded)
  math(EXPR wanted "${n_resizes} + ${n_strings}")
  if(NOT n_bounded EQUAL wanted)
    message(FATAL_ERROR "${header}: ${n_bounded} of ${wanted} array and string decoders bounded; "
                        "lcm-gen's output changed: update lcmtypes/bound_decoders.cmake")
  endif()
  file(WRITE "${header}" "${text}")
endforeach()
