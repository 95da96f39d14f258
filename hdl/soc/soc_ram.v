// soc_ram: the SoC's word RAM (32-bit words) with two ports, in the pattern Yosys infers as
// block RAM (DP16KD on ECP5): each port in its own clocked block, registered reads, and one
// write port with byte enables. A read on port B in the clock it writes returns the old word.
`timescale 1ns / 1ps
`default_nettype none

module soc_ram #(
    parameter integer WORDS = 1024,      // 32-bit words
    parameter INIT_FILE = ""             // $readmemh image loaded at configuration ("" none)
) (
    input  wire                     clk,      // the one clock
    input  wire                     a_en,     // port A: read the word at a_addr this clock
    input  wire [$clog2(WORDS)-1:0] a_addr,   // port A: word address
    output reg  [31:0]              a_rdata,  // port A: the word read, the clock after a_en
    input  wire                     b_en,     // port B: access the word at b_addr this clock
    input  wire [3:0]               b_we,     // port B: byte lanes written (0: a read)
    input  wire [$clog2(WORDS)-1:0] b_addr,   // port B: word address
    input  wire [31:0]              b_wdata,  // port B: the word written (lanes by b_we)
    output reg  [31:0]              b_rdata   // port B: the word read (before the write)
);
    reg [31:0] mem [0:WORDS-1];
    initial begin
        a_rdata = 32'd0;
        b_rdata = 32'd0;
    end
    generate if (INIT_FILE != "") begin : init
        initial $readmemh(INIT_FILE, mem);
    end endgenerate

    always @(posedge clk) if (a_en) a_rdata <= mem[a_addr];

    integer lane;
    always @(posedge clk) begin
        if (b_en) begin
            for (lane = 0; lane < 4; lane = lane + 1)
                if (b_we[lane]) mem[b_addr][8 * lane +: 8] <= b_wdata[8 * lane +: 8];
            b_rdata <= mem[b_addr];
        end
    end
endmodule
`default_nettype wire
