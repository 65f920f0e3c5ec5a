; The ROM of tests/scenarios/search/search_kat.yaml (issue #46): a known answer for `rcsim search`.
; Built at test time:  nasm -f bin -o search_kat.bin search_kat.asm
;
; Ports 0 and 1 each get one character. Port 0's handler (IR0) reads it and then keeps IF = 0 for
; 1000 NOPs (about 375 us) before its EOI and IRET; port 1's handler (IR1) only reads, sends its
; EOI and returns. When port 1's character arrives while port 0's handler runs, IR1 waits for the
; rest of that handler: report.json interrupts.rs232_1.latency_us.max, as a function of port 1's
; send time T1, is one sawtooth tooth. Its top, in clocks, is derived below.
;
; The board (docs/system.md §2, §3): ROM F0000-FFFFF, RAM 00000-0FFFF; 82510 #n register r at
; I/O 0x80 + 0x10 n + 2 r, on IR n; the 8259A at 0xC0/0xC2. Nothing but the two handlers runs
; after start-up (the main program is HLT), so the handlers save no registers.
;
; ---- The latency of IR1 (8086-2 at 8 MHz: 1 clock = 125 ns) ----------------------------------
; References as in tests/scenarios/board/latency_cause_kat_test.cpp and probe_known_answer_test.cpp:
;   [TAB] 8086 clock tables, instruction already in the queue: NOP 3, MOV AL,imm8 4,
;         IN AL,imm8 10, OUT imm8,AL 10 (plus the I/O wait state).
;   [BRD] wait states: ROM 1 (a code fetch T1 T2 T3 Tw T4 = 5 clocks for 2 bytes), RAM 0, I/O 1.
;   [BIU] the bus-interface rules of probe_known_answer_test.cpp: an EU request on an idle bus
;         gets T1 three clocks later; one made during a prefetch's T1/T2 follows its T4 directly,
;         one made in its T3/T4 three clocks after T4; a fetch whose T2 sees <= 4 bytes queued is
;         followed by the next back to back.
;   [DS]  INTR is sampled at instruction boundaries (a boundary at clock edge c sees the level held
;         before c); a halted CPU's boundary is the first clock edge after the rise.
;   [PIC] the 8259A freezes its choice at the first INTA (pic8259/README.md "INTA sequence"):
;         IR0 wins over IR1 if it has risen by then, whichever woke the CPU.
;   (E) (H) (T) (C) the derivations of probe_known_answer_test.cpp: (E) entry from a boundary B
;         with the bus idle: INTA1 at B+4, the handler's first fetch at h = B+52, first_isr =
;         B+57; (H)/(T) the MOV AL,20h / OUT 0C0h,AL / IRET tail: its return fetch (iret_done)
;         33 clocks after the EOI's T1; (C) after a return fetch at r: the first opcode read at
;         r+5, its boundary at r+6.
;
; B = the boundary at which the halted CPU takes IR0's request. The HLT is always reached through
; a JMP (idle below), so the bus is idle there and (E) holds.
;   (1) B -> first_isr0                                                                 57  (E)
;   (2) first_isr0 -> the EOI's T1                                                    3028
;       h+7 IN opcode read (the push of IP overlaps, as (H)), h+9 port byte, h+10 widen; the
;       read requested at h+11 is in T3 of the prefetch of isr_port0+2 (T1 h+9, back to back
;       after the push) -> T1 three clocks after its T4 (h+13) = h+16 [BIU], T4 h+20 (1 Tw):
;       the IN takes 14 clocks here (10 + 1 Tw [TAB][BRD], 3 lost to the prefetch)       14
;       h+21+3k: the read of NOP k (k = 0..999), 3 clocks each [TAB]; the queue never runs dry
;       (2 bytes per 5-clock fetch [BRD] against 1 byte per 3 clocks)                  3000
;       m = h+3021 MOV AL,20h read; m+4 OUT read [TAB]                                    4
;       m+6 port byte, m+7 m+8 widen and address; the write requested at m+9 on an idle bus
;       (the queue full after the NOPs) -> its T1 = the EOI at m+12 [BIU]                 8
;       so the EOI is at h+3033 = first_isr0 + 3028 (first_isr0 = h+5; 14+3000+4+8 = 3026
;       from h+7 = first_isr0+2)
;   (3) the EOI -> the return fetch's T1 R (iret_done of IR0)                               33  (H)(T)
;       The EOI clears IS0: the 8259A presents IR1 at once (INT up at the EOI's T1); the IRET
;       restores IF = 1.
;   (4) R -> IR1's INTA1                                                                 12
;       R+5 first opcode read at the return address (JMP idle), R+6 its boundary [C]: IR1 taken
;       there; one clock [INT]; the INTA request at R+7 finds the prefetch that follows the
;       return fetch back to back (T1 R+5) in its T3 -> T1 three clocks after its T4 (R+9)
;       = R+12 [BIU]
;   (5) IR1's INTA1 -> first_isr1                                                        53  (E)
;   C = first_isr1 - B = 57 + 3028 + 33 + 12 + 53                                      3183 clocks
;                                                                                   = 397.875 us
; IR1's latency is first_isr1 - t1 = C + B - t1, for every t1 that IR0's service holds:
;   * t0, t1 = the IR rises: a character enters the RX FIFO at the end of its first stop bit,
;     11 bit times after at_ms (1145.833 us at 9600 bps, docs/serial.md), the same on both ports.
;     at_ms 10 on port 0: t0 = 11145.8333 us = clock 89166.667, B = B0 = clock 89167 (B0 - t0 =
;     1/3 clock).
;   * t0 <= t1 < R+6 (IR1 after IR0, before the boundary that takes it): B = B0, latency
;     C + B0 - t1, falling one clock per clock from C + 1/3 = 3183.33 clocks = 397.917 us at
;     T1 = 10.000 ms to about 59 clocks at R+6 = B0 + 57 + 3028 + 33 + 6 = clock 92291,
;     T1 = 10.390542 ms: the tooth's edge.
;   * t1 < t0 with IR0 risen before INTA1 = floor(t1)+1+4 [DS][PIC] (t1 >= clock 89162, T1 >=
;     9.999417 ms): IR1 woke the CPU but IR0 is served first, B = floor(t1)+1 and the latency is
;     C + (floor(t1)+1 - t1), in (3183, 3184]: the ANALYTIC MAXIMUM is C + 1 = 3184 clocks =
;     398.000 us, when IR1 rises on a clock edge in that window (T1 = 10 ms - (2/3 + j) clocks,
;     j = 0..4, e.g. 9.99991666666667 ms). On a T1 grid off those edges the top is 3183.33
;     clocks = 397.917 us at T1 = 10.000 ms.
;   * elsewhere: the entry only. IR1 before that window is served first; IR1 after the edge
;     finds the CPU halted: 57 + (floor(t1)+1 - t1) clocks, 57.33 clocks = 7.167 us for T1 on a
;     grid of whole microseconds (t1 = 2/3 clock past an edge), or in the idle loop's JMP or HLT
;     just past the edge: up to 73.33 clocks = 9.167 us (T1 = 10.39075 ms).
; Not derived clock by clock: (2)'s IN and OUT meet the prefetches at phases of the queue that
; the derivation names but the tables do not give; K = 999 and 1001 NOPs measure C - 4 and C + 3
; (3 clocks a NOP, +-1 from the prefetch phase at the end of the run).
;
; Measured (rcsim run, 352 values of T1 in [9.5, 11.5] ms, 10 us apart and down to 1/16 us near
; 10 ms and at the edge): maximum 398.000 us = 3184 clocks at T1 = 9.999667, 9.999792, 9.999917
; ms (IR1 on a clock edge; single runs: also 9.999417 and 9.999542, and 7.125 us just below
; 9.999417); 397.917 us at T1 = 10.000 ms; on the tooth latency = 397.917 us - (T1 - 10 ms)
; exactly; 7.417 us at T1 = 10.3905 ms, 9.167 us at 10.39075 ms (the idle loop), 7.167 us from
; 10.39275 ms on; 7.13-7.23 us below the window (IR1 served first). The
; phases of the T1 = 10 ms run: (1) 57, (2) 3028, (3) 33, (4) 12, (5) 53 clocks.
; ------------------------------------------------------------------------------------------------
        cpu     8086
        bits    16
        org     0                   ; ROM offset 0 = F000:0000 (physical F0000)

PIC_A0  equ     0xC0
PIC_A1  equ     0xC2
U0      equ     0x80                ; 82510 #0: register r at U0 + 2r
U1      equ     0x90                ; 82510 #1
HOLD    equ     1000                ; NOPs of port 0's handler with IF = 0 (3000 clocks, 375 us)

; 82510 register offsets (x 2: the low byte lane, docs/system.md §3.2) and values, as the
; firmware's fw.h / hw.c uart_init
R_RXD   equ     0                   ; bank 0 (DLAB = 0) and bank 1
R_BAL   equ     0                   ; bank 0, DLAB = 1
R_BAH   equ     2                   ; bank 0, DLAB = 1
R_GER   equ     2                   ; bank 0, DLAB = 0
R_BANK  equ     4                   ; write, every bank
R_LCR   equ     6                   ; bank 0
R_IMD   equ     8                   ; bank 2
R_CLCF  equ     0                   ; bank 3
R_BACF  equ     2                   ; bank 3
R_RCM   equ     10                  ; bank 1
R_ICM   equ     14                  ; bank 1

; One 82510 at %1 for 9600,8E1 with the Rx FIFO interrupt (one character) on, bank 0 left
; selected: the firmware's uart_init sequence, without what this ROM does not use (BRGB timer,
; modem and Tx set-up, the Rx machine's error interrupt).
%macro  UART_INIT 1
        mov     al, 0x20            ; BANK <- 1 (WORK)
        out     %1 + R_BANK, al
        mov     al, 0x10            ; ICM: software reset (leaves bank 0 selected)
        out     %1 + R_ICM, al
        mov     al, 0x00            ; BANK <- 0 (NAS)
        out     %1 + R_BANK, al
        mov     al, 0x9B            ; LCR: DLAB | 8 bits, even parity, 1 stop (0x1B)
        out     %1 + R_LCR, al
        mov     al, 60              ; BRGA divisor 60: 18.432 MHz / (32 x 60) = 9600 bps
        out     %1 + R_BAL, al
        mov     al, 0
        out     %1 + R_BAH, al
        mov     al, 0x1B            ; LCR: 8E1, DLAB = 0
        out     %1 + R_LCR, al
        mov     al, 0x40            ; BANK <- 2 (GEN)
        out     %1 + R_BANK, al
        mov     al, 0x00            ; IMD: 4-byte Rx FIFO, automatic INT (FMD stays 0: threshold 1)
        out     %1 + R_IMD, al
        mov     al, 0x60            ; BANK <- 3 (MODM)
        out     %1 + R_BANK, al
        mov     al, 0x50            ; CLCF: Rx and Tx clocks from BRGA, 16x
        out     %1 + R_CLCF, al
        mov     al, 0x04            ; BACF: BRGA is a baud-rate generator
        out     %1 + R_BACF, al
        mov     al, 0x20            ; BANK <- 1 (WORK)
        out     %1 + R_BANK, al
        mov     al, 0xB0            ; RCM: receiver enable, flush the Rx FIFO and machine
        out     %1 + R_RCM, al
        mov     al, 0x04            ; ICM: status clear
        out     %1 + R_ICM, al
        mov     al, 0x00            ; BANK <- 0 (NAS): GER and RXD
        out     %1 + R_BANK, al
        mov     al, 0x01            ; GER: Rx FIFO interrupt only
        out     %1 + R_GER, al
%endmacro

start:  cli
        xor     ax, ax
        mov     ss, ax
        mov     sp, 0x0800
        mov     ds, ax
        mov     word [0x20 * 4], isr_port0  ; vector 20h (IR0): F000:isr_port0
        mov     word [0x20 * 4 + 2], 0xF000
        mov     word [0x21 * 4], isr_port1  ; vector 21h (IR1): F000:isr_port1
        mov     word [0x21 * 4 + 2], 0xF000
        UART_INIT U0
        UART_INIT U1
        mov     al, 0x13            ; ICW1: edge, single, ICW4 (the firmware's pic_init)
        out     PIC_A0, al
        mov     al, 0x20            ; ICW2: IR n -> vector 20h + n
        out     PIC_A1, al
        mov     al, 0x01            ; ICW4: 8086 mode, normal EOI
        out     PIC_A1, al
        mov     al, 0xFC            ; OCW1: IR0 and IR1 only
        out     PIC_A1, al
        sti
        jmp     idle                ; in the STI's shadow; every HLT is reached through a JMP
idle:   hlt                         ; (bus idle when an interrupt wakes it: (E) holds)
        jmp     idle

        align   2                   ; the derivation's fetches start at an even address
isr_port0:
        in      al, U0 + R_RXD      ; the character: the Rx FIFO empties, INT falls
        times   HOLD nop            ; IF = 0 all along (the entry cleared it)
        mov     al, 0x20            ; non-specific EOI
        out     PIC_A0, al
        iret

        align   2
isr_port1:
        in      al, U1 + R_RXD
        mov     al, 0x20
        out     PIC_A0, al
        iret

        times   0xFFF0 - ($ - $$) db 0xFF
        jmp     0xF000:start        ; the reset vector: FFFF:0000 = physical FFFF0
        times   0x10000 - ($ - $$) db 0xFF
