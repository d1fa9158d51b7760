# Illumination propagation (Ropinski 2010, Sunden 2015): its sources, its kernel contract
# (cmake/kernel_contract.cmake): the illumination volume the march reads through its hooks in
# vx_illumination.h, and its settings (cmake/method_settings.cmake).
list(APPEND VOXLUX_LIGHTING_SOURCES
  src/lighting/propagation/cpu_propagation.cpp src/lighting/propagation/emitted_light.cpp
  src/lighting/propagation/light_sweeps.cpp src/lighting/propagation/propagation_method.cpp
  src/lighting/propagation/propagation_passes.cpp src/lighting/propagation/propagation_stages.cpp)
voxlux_kernel_method(propagation
  TYPES lighting/propagation/kernel/vx_propagation_types.h
  BLOCK VxPropagationMarch
  MARCH lighting/propagation/kernel/vx_illumination.h
  SAMPLE VxPropagationSample
  HOOKS varies shadows direct indirect
  PASSES lighting/propagation/kernel/vx_propagation.h
  ENTRIES lighting/propagation/propagate.comp
  UNIFORMS "PropParams VxPropParams Q"
  MARCH_ARRAYS "Illumination float vx_illum illum"
  PASS_ARRAYS "PropSigma float vx_prop_sigma prop_sigma" "SliceIn float vx_prop_prev prop_prev" "SweepInput float vx_prop_in prop_in"
  BINDINGS VOLUME SLICE_OUT)
voxlux_method_settings(propagation TYPE PropagationSettings
  SHADOWS propagation Propagation "direct and indirect light read from the illumination volume")
