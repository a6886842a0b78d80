// Fuzz target: the scene JSON reader (load_scene, physics/io/scene.h). Bad input must be an
// InputError (one line); an accepted scene is written back (scene_to_json) and parsed again.
#include <cstring>

#include "fuzz/fuzz_common.h"
#include "ldlpgs/physics/io/scene.h"

using namespace ldlpgs;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::fuzz_size_limits();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::MemoryFile in;
  const std::string path = in.write(data, size);
  Mechanism m;
  try {
    m = load_scene(path);
  } catch (const InputError& e) {
    // The message is one bounded line of printable characters: a few
    // hundred characters, each quote of the input bounded.
    const size_t length = std::strlen(e.what());
    if (length > 1000) fuzz::finding("a message of " + std::to_string(length) + " characters: " + e.what());
    for (const char* c = e.what(); *c; ++c)
      if (static_cast<unsigned char>(*c) < 0x20 || static_cast<unsigned char>(*c) >= 0x7f)
        fuzz::finding(std::string("a raw byte in the message: ") + e.what());
    return 0;
  } catch (const ArgumentError&) {
    return 0;
  } catch (const std::exception& e) {
    fuzz::finding(std::string("unexpected exception: ") + e.what());
  }
  // The writer's JSON of an accepted scene must not crash the reader either (whether it is
  // accepted again is the physics layer's round-trip test, tests/physics/scene_test.cpp).
  fuzz::accepted([&] { parse_scene(scene_to_json(m), "round trip"); });
  return 0;
}
