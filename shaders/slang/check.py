"""Compile every .hlsl file in a folder with Slang (slangpy's CPU device), warnings as
errors: each file is a fragment shader whose entry point is `main`. Prints one line per
file; exits 1 if any fails. Used by shaders/tests/slang.rs."""
import os
import sys

import slangpy as spy

folder = sys.argv[1]
device = spy.Device(type=spy.DeviceType.cpu, compiler_options=spy.SlangCompilerOptions({"warnings_as_errors": ["all"]}))
failures = 0
for name in sorted(f for f in os.listdir(folder) if f.endswith(".hlsl")):
    source = open(os.path.join(folder, name)).read().replace("float4 main(", '[shader("fragment")]\nfloat4 main(', 1)
    try:
        module = device.load_module_from_source(name.replace(".", "_").replace("-", "_"), source)
        device.link_program([module], [module.entry_point("main")])
        print(f"{name}: ok")
    except Exception as e:  # slangpy raises RuntimeError with the compiler's diagnostics
        failures += 1
        lines = [l for l in str(e).splitlines() if "error" in l or "-->" in l or "|" in l]
        print(f"{name}: FAILED\n  " + "\n  ".join(lines[:12]))
sys.exit(1 if failures else 0)
