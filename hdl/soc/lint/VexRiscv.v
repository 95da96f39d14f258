// VexRiscv's port list, without its body: the CPU as a black box for `fusesoc run
// --target=lint coopwin:coopwin:soc` (hdl/soc/coopwin_soc.core), so that Verilator -Wall
// lints our files only and needs no pip package. The real core is pythondata-cpu-vexriscv's
// generated VexRiscv_IMAC.v (scripts/soc.sh, scripts/soc-ecp5.sh); the header below is its
// `module VexRiscv (` ... `);` copied verbatim, and hdl/tests/fusesoc.rs checks that it still
// is. A black box drives nothing and reads nothing, hence the two waivers.
`default_nettype none
/* verilator lint_off UNDRIVEN */
/* verilator lint_off UNUSEDSIGNAL */
module VexRiscv (
  input      [31:0]   externalResetVector,
  input               timerInterrupt,
  input               softwareInterrupt,
  input      [31:0]   externalInterruptArray,
  output reg          iBusWishbone_CYC,
  output reg          iBusWishbone_STB,
  input               iBusWishbone_ACK,
  output              iBusWishbone_WE,
  output     [29:0]   iBusWishbone_ADR,
  input      [31:0]   iBusWishbone_DAT_MISO,
  output     [31:0]   iBusWishbone_DAT_MOSI,
  output     [3:0]    iBusWishbone_SEL,
  input               iBusWishbone_ERR,
  output     [2:0]    iBusWishbone_CTI,
  output     [1:0]    iBusWishbone_BTE,
  output              dBusWishbone_CYC,
  output              dBusWishbone_STB,
  input               dBusWishbone_ACK,
  output              dBusWishbone_WE,
  output     [29:0]   dBusWishbone_ADR,
  input      [31:0]   dBusWishbone_DAT_MISO,
  output     [31:0]   dBusWishbone_DAT_MOSI,
  output     [3:0]    dBusWishbone_SEL,
  input               dBusWishbone_ERR,
  output     [2:0]    dBusWishbone_CTI,
  output     [1:0]    dBusWishbone_BTE,
  input               clk,
  input               reset
);
endmodule
/* verilator lint_on UNUSEDSIGNAL */
/* verilator lint_on UNDRIVEN */
`default_nettype wire
