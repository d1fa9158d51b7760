# Extinction-SAT lighting (Schlegel 2011): its sources, its kernel contract
# (cmake/kernel_contract.cmake): the light cache the march reads through its hooks in vx_cache.h,
# and its settings (cmake/method_settings.cmake).
list(APPEND VOXLUX_LIGHTING_SOURCES
  src/lighting/extinction_sat/cpu_light_pass.cpp src/lighting/extinction_sat/extinction_sat_method.cpp
  src/lighting/extinction_sat/extinction_sat_stages.cpp src/lighting/extinction_sat/sat_passes.cpp
  src/lighting/extinction_sat/summed_volume.cpp)
voxlux_kernel_method(extinction_sat
  TYPES lighting/extinction_sat/kernel/vx_sat_types.h
  BLOCK VxSatMarch
  MARCH lighting/extinction_sat/kernel/vx_cache.h
  SAMPLE VxSatSample
  HOOKS varies shadows shadow ambient
  PASSES lighting/extinction_sat/kernel/vx_sat.h
  ENTRIES lighting/extinction_sat/sat_scan.comp lighting/extinction_sat/light_cache.comp
  UNIFORMS "SatParams VxSatParams S"
  MARCH_ARRAYS "LightCache float vx_cache cache"
  PASS_ARRAYS "Sat uint vx_sat_word sat"
  BINDINGS NEEDED CHANNEL SAT_SCAN)
voxlux_method_settings(extinction_sat TYPE ExtinctionSatSettings
  SHADOWS sat_cone SatCone "SAT-cone shadows read from the light cache")
