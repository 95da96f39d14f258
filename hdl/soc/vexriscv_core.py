"""FuseSoC generator (coopwin_soc.core's `vexriscv`): the SoC's CPU as a generated core, because
its Verilog is pip's pythondata-cpu-vexriscv (VexRiscv_<variant>.v), outside our core folders.
The file is copied into the generated core's folder, so the build names it there."""
import os
import shutil

import pythondata_cpu_vexriscv
from fusesoc.capi2.generator import Generator

gen = Generator()
name = "VexRiscv_{}.v".format(gen.config["variant"])
shutil.copy(os.path.join(pythondata_cpu_vexriscv.data_location, name), name)
gen.add_files([name], file_type="verilogSource")
gen.write()
