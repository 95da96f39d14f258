// soc_ram: the SoC's word RAM (32-bit words) with two ports, in the pattern Yosys infers as
// block RAM (DP16KD on ECP5, 2 KiB a block: 2048x9 a byte lane): each port in its own clocked
// block, registered reads, a memory a byte lane (8 bits wide, its own write enable).
// A write on port B leaves that lane's read data as it was.
// Port A reads the byte port B writes on the same clock (write-first across the ports). With
// port A reading the old byte instead, Yosys 0.23 emulates that read-before-write at two
// DP16KD a 2 KiB lane (with a 256 KiB program RAM the SoC took 298 of the 85F's 208 DP16KD);
// with this bypass, a compare and a mux in logic, it maps one (256 KiB in 128 blocks).
`timescale 1ns / 1ps
`default_nettype none

module soc_ram #(
    parameter integer WORDS = 1024,      // 32-bit words
    parameter INIT_FILE = ""             // "" none, else lane k is loaded from INIT_FILE + "k" ($readmemh, one byte a line)
) (
    input  wire                     clk,      // the one clock
    input  wire                     a_en,     // port A: read the word at a_addr this clock
    input  wire [$clog2(WORDS)-1:0] a_addr,   // port A: word address
    output wire [31:0]              a_rdata,  // port A: the word read, the clock after a_en
    input  wire                     b_en,     // port B: access the word at b_addr this clock
    input  wire [3:0]               b_we,     // port B: byte lanes written (0: a read)
    input  wire [$clog2(WORDS)-1:0] b_addr,   // port B: word address
    input  wire [31:0]              b_wdata,  // port B: the word written (lanes by b_we)
    output wire [31:0]              b_rdata   // port B: the word read (lanes not written)
);
    genvar k;
    generate for (k = 0; k < 4; k = k + 1) begin : lane
        reg [7:0] mem [0:WORDS-1];
        reg [7:0] a_q = 8'd0, b_q = 8'd0;
        localparam [7:0] DIGIT = 8'd48 + k;  // the lane's file suffix, "0".."3"
        if (INIT_FILE != "") begin : init
            initial $readmemh({INIT_FILE, DIGIT}, mem);
        end
        always @(posedge clk) if (a_en) a_q <= b_en && b_we[k] && b_addr == a_addr ? b_wdata[8 * k +: 8] : mem[a_addr];
        always @(posedge clk) begin
            if (b_en) begin
                // A write does not read (no-change): the bus ignores a write's read data,
                // and Yosys maps a read-before-write port at twice the DP16KD.
                if (b_we[k]) mem[b_addr] <= b_wdata[8 * k +: 8];
                else b_q <= mem[b_addr];
            end
        end
        assign a_rdata[8 * k +: 8] = a_q;
        assign b_rdata[8 * k +: 8] = b_q;
    end endgenerate
endmodule
`default_nettype wire
