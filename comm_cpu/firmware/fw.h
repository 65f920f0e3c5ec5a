/*
 * rcsim communication firmware -- shared definitions.
 *
 * Target: Intel 8086-2 @ 8 MHz, compiled with Debian bcc (-0 -ansi), 16-bit int; the interrupt
 * paths are in isr.s, whose constants repeat the ones below (the build checks they agree).
 * Memory model: one data segment DS = SS = ES = DATA_SEG (physical 0x00400) holding the
 * variables, the stack and the three 20 KB port buffers; code runs from ROM at F000:0000.
 * See docs/firmware.md for the memory map, the state machine and the register contract.
 */
#ifndef RCSIM_FW_H
#define RCSIM_FW_H

/* ---- board (docs/system.md section 2, section 3) ------------------------------------ */
#define NO_PORT       3
#define DATA_SEG      0x0040          /* physical 0x00400, right above the vector table */
#define STACK_TOP     0x0C00          /* DS offset: the stack grows down from phys 0x01000 */
#define BUF_BASE      0x0C00          /* DS offset of port 0's 20 KB buffer (phys 0x01000) */
#define BUF_SIZE      0x5000          /* 20 KB per port */
#define RXBUF_SIZE    0x2800          /* first 10 KB: frame received from the host */
#define TXBUF_SIZE    0x2800          /* last 10 KB: frame to send to the host */

/* 8259A at 0xC0 (A0 = 0) and 0xC2 (A0 = 1) */
#define PIC_A0        0xC0
#define PIC_A1        0xC2
#define PIC_ICW1      0x13            /* D4=1, edge (LTIM=0), single (SNGL=1), IC4=1 */
#define PIC_ICW2      0x20            /* IR n -> vector 0x20 + n */
#define PIC_ICW4      0x01            /* 8086 mode, normal EOI, non-buffered, no SFNM */
#define PIC_OCW1      0xF0            /* IR0..IR3 unmasked, IR4..IR7 masked */
#define PIC_EOI_ROT   0xA0            /* OCW2: rotate on non-specific EOI */
#define IRQ_DPRAM     3               /* IR3 = IDT7130 INT_L */
#define VEC_BASE      0x20

/* 82510 #n register r at 0x80 + 0x10 n + 2 r */
#define UART_BASE(p)  (0x80 + ((p) << 4))
#define R(r)          ((r) << 1)
/* every bank */
#define U_GIR         R(2)            /* read: general interrupt register */
#define U_BANK        R(2)            /* write: bank select */
#define BANK_NAS      0x00            /* bank 0: 8250A compatible */
#define BANK_WORK     0x20            /* bank 1: working bank (normal operation) */
#define BANK_GEN      0x40            /* bank 2: general configuration */
#define BANK_MODM     0x60            /* bank 3: modem / clock configuration */
#define BANK_MASK     0x60
/* bank 0 */
#define U_BAL         R(0)            /* DLAB = 1 */
#define U_BAH         R(1)            /* DLAB = 1 */
#define U_GER         R(1)            /* DLAB = 0 */
#define U_LCR         R(3)
#define U_MCR         R(4)
/* bank 1 */
#define U_RXD         R(0)
#define U_TXD         R(0)
#define U_TMST        R(3)            /* read */
#define U_TMCR        R(3)            /* write */
#define U_FLR         R(4)
#define U_RST         R(5)            /* read */
#define U_RCM         R(5)            /* write */
#define U_MSR         R(6)            /* read */
#define U_TCM         R(6)            /* write */
#define U_GSR         R(7)            /* read */
#define U_ICM         R(7)            /* write */
/* bank 2 */
#define U_FMD         R(1)
#define U_TMD         R(3)
#define U_IMD         R(4)
#define U_RIE         R(6)
#define U_RMD         R(7)
/* bank 3 */
#define U_CLCF        R(0)            /* DLAB = 0 */
#define U_BBL         R(0)            /* DLAB = 1 */
#define U_BACF        R(1)            /* DLAB = 0 */
#define U_BBH         R(1)            /* DLAB = 1 */
#define U_BBCF        R(3)
#define U_PMD         R(4)
#define U_MIE         R(5)
#define U_TMIE        R(6)

/* values */
#define LCR_8E1       0x1B            /* 8 bits, 1 stop, even parity */
#define LCR_DLAB      0x80
#define BAUD_DIV      60              /* 18.432 MHz / (32 * 9600) */
#define MCR_ON        0x0B            /* DTR, RTS, OUT2 */
#define GER_RXF       0x01            /* Rx FIFO (data available) */
#define GER_RXM       0x04            /* Rx machine (errors, break) */
#define GER_TXF       0x02            /* Tx FIFO at or below its threshold (0: empty) */
#define GER_TXM       0x10            /* Tx machine: transmitter idle (FIFO empty, last stop bit sent) */
#define GER_TIMER     0x20
#define GER_RX        (GER_RXF | GER_RXM)
#define GER_ON(p)     ((p) == TICK_PORT ? (GER_RX | GER_TIMER) : GER_RX)
#define GIR_NONE      0x01            /* IP is active low: 1 = nothing pending */
#define GIR_VEC       0x0E
#define GIR_TIMER     0x0A
#define GIR_TXM       0x08
#define GIR_RXM       0x06
#define GIR_RXF       0x04
#define GIR_TXF       0x02
#define GIR_MODEM     0x00
#define RST_OE        0x02
#define RST_PE        0x04
#define RST_FE        0x08
#define RST_BKD       0x10
#define RIE_ERRS      0x1E            /* OE, PE, FE, break detect */
#define RCM_START     0xB0            /* RX enable + flush RX FIFO + flush RX machine */
#define TCM_START     0x0E            /* TX enable + flush TX FIFO + flush TX machine */
#define ICM_RESET     0x10            /* software reset (leaves bank 0 selected) */
#define ICM_STC       0x04            /* status clear */
#define ICM_INTA      0x08            /* interrupt acknowledge: INT falls, re-rises if still pending */
#define FLR_TFL       0x07            /* TX FIFO level 0..4 */
#define FLR_RFL       0x70            /* RX FIFO level 0..4 */
#define FLR_RFL_SHIFT 4
#define TXFIFO_DEPTH  4
#define RXFIFO_DEPTH  4
#define ISR_VISITS    1               /* sources handled per RS-232 interrupt, at most */
#define CLCF_BRGA16   0x50            /* RX and TX clocks from BRGA, 16x */
#define BACF_BRG      0x04            /* BRGA is a baud-rate generator */
#define BBCF_TIMER    0x00            /* BRGB is a timer, system clock */
#define TMIE_TB       0x02            /* timer B interrupt enable */
#define TMCR_GO_B     0x22            /* STB (load + start timer B) | TGB (count enable) */
#define TMST_TB       0x02            /* timer B expired */

/* the millisecond tick: 82510 #0 BRGB in timer mode, auto-reloading (periodic) */
#define TICK_PORT     0
#define TICK_DIV      9216            /* 1 ms at 9.216 MHz (= 18.432 MHz / 2, the BRG clock) */

/* ---- DP-RAM (docs/system.md section 4), left port at D000:0000 ------------------------ */
#define DP_SEG        0xD000
#define CHUNK         339
#define AREA          340
#define PFLAG(p)      ((p) * AREA + CHUNK)
#define INT2EXT       0x3FE           /* main -> comm mailbox (INT_L, IR3) */
#define INT2RBT       0x3FF           /* comm -> main mailbox (INT_R) */
#define P_FREE        0
#define EXT_USE       1
#define RBT_USE       2
#define MB_CHUNK      0x10            /* new chunk in data[p] */
#define MB_ACK        0x20            /* chunk consumed */
#define MB_RESET      0x30            /* reset port p */
#define MB_GAVE_UP    0x40            /* response given up, never left whole: the host has not got it */
#define MB_GAVE_UP_TX 0x50            /* response given up after it left whole at least once, no EOT */

/* ---- protocol (docs/system.md section 5, section 6) ----------------------------------- */
#define SOH 0x01
#define STX 0x02
#define ETX 0x03
#define EOT 0x04
#define ENQ 0x05
#define ACK 0x06
#define NAK 0x15

#define MAX_DATA      8192
#define MIN_FRAME     9               /* SOH T1 T2 STX B1 B2 C1 C2 ETX */
#define MAX_FRAME     (MIN_FRAME + MAX_DATA)

/* timers in ms (ticks) */
#define T1_MS         50              /* ENQ -> ACK/NAK, ETX -> EOT/NAK, ACK -> first byte */
#define T2_MS         20              /* longest gap inside a frame */
#define RETRY_MS      10              /* back-off: 10 ms x attempt */
#define MAX_RETRY     3
#define DP_ACK_MS     1000            /* main CPU must consume a chunk within this */
#define TXQ           8               /* frames queued per port (power of two) */
#define AREA_STALE_MS 1000            /* RBT_USE without a chunk word this long: abandoned */
#define MB_WAIT_MS    5               /* wait at most this for the main CPU to empty int2rbt */
#define QUENCH_MS     10              /* a port that overran: its receiver interrupts stay off this long */

/* step[port] -- the paper's program steps */
#define ST_IDLE       0
#define ST_RECV       1               /* receiving from the host; full chunks go to DP-RAM */
#define ST_DONE       2               /* frame good (EOT sent); forward the rest to DP-RAM */
#define ST_DROP       3               /* frame dropped (NAK sent / T2 gap); clean up */
#define ST_RESET      4               /* port reset asked for: the main loop runs it (port_reinit) */
#define ST_SEND_ENQ   10
#define ST_WAIT_ACK   11
#define ST_SEND       12
#define ST_WAIT_EOT   13

/* rx_bad bits */
#define BAD_LINE      0x01            /* parity, framing or overrun error */
#define BAD_CHAR      0x02            /* byte outside the allowed set / misplaced control byte */
#define BAD_LONG      0x04            /* frame over MAX_FRAME */

/* ---- assembly helpers (crt0.s) -------------------------------------------------------- */
unsigned char inb(unsigned port);
void outb(unsigned port, unsigned char value);
unsigned char dp_rd(unsigned offset);
void dp_wr(unsigned offset, unsigned char value);
unsigned mul_div_up(unsigned a, unsigned b, unsigned c);   /* ceil(a * b / c), 0xFFFF if larger */
unsigned irq_off(void);               /* CLI, returns the previous FLAGS */
void irq_restore(unsigned flags);
void irq_on(void);

/* ---- firmware state (defined in main.c) ------------------------------------------------ */
extern unsigned ticks;                      /* milliseconds since start-up (wraps) */
extern unsigned unexpected;                 /* interrupts on vectors we do not use */
extern unsigned char step[NO_PORT];         /* the paper's program step */
extern unsigned char gen[NO_PORT];          /* bumped by every port reset */
extern unsigned char *rxbuf[NO_PORT];
extern unsigned char *txbuf[NO_PORT];
extern unsigned area[NO_PORT];              /* DP-RAM offset of data[p] */
extern unsigned port_div[NO_PORT];          /* BRGA divisor per port (patchable) */
extern unsigned char port_lcr[NO_PORT];     /* LCR per port (patchable) */
extern unsigned tick_div;                   /* BRGB divisor of the 1 ms tick (patchable) */
/* receive side (host -> main CPU) */
extern unsigned rx_len[NO_PORT];            /* bytes stored in rxbuf (SOH .. ETX) */
extern unsigned rx_fwd[NO_PORT];            /* bytes already written to DP-RAM */
extern unsigned rx_t[NO_PORT];              /* tick of the last byte (or of our ACK) */
extern unsigned char rx_sum[NO_PORT];       /* running sum of every byte after SOH */
extern unsigned char rx_bad[NO_PORT];       /* BAD_* bits of the frame being received */
extern unsigned char chunk_out[NO_PORT];    /* a chunk waits for the main CPU's ACK word */
extern unsigned chunk_t[NO_PORT];
/* transmit side (main CPU -> host): txbuf is a ring of whole frames, oldest sent first */
extern unsigned char tx_have[NO_PORT];      /* complete frames queued in txbuf */
extern unsigned char txq_head[NO_PORT];     /* txq_len index of the frame being sent */
extern unsigned txq_len[NO_PORT][TXQ];      /* lengths of the queued frames */
extern unsigned tx_rd[NO_PORT];             /* ring offset of the frame being sent */
extern unsigned tx_wr[NO_PORT];             /* ring offset where the next chunk goes */
extern unsigned tx_used[NO_PORT];           /* bytes in the ring (queued + partial) */
extern unsigned tx_part[NO_PORT];           /* bytes of the frame still being assembled */
extern unsigned char chunk_pending[NO_PORT];/* a chunk from the main CPU waits for ring space */
extern unsigned tx_pos[NO_PORT];            /* bytes of the current frame given to the 82510 */
extern unsigned tx_t[NO_PORT], tx_wait[NO_PORT];
extern unsigned char tx_try[NO_PORT];
extern unsigned char tx_whole[NO_PORT];     /* the frame being sent left whole at least once */
extern unsigned char txe_wait[NO_PORT];     /* a timer starts when the transmitter is idle */
extern unsigned t1_lim[NO_PORT];            /* T1 + one character, in ticks (see main()) */
extern unsigned char reset_due[NO_PORT];    /* port reset asked for (1; | 2: tell the main CPU), waiting
                                             * for the EOT'd frame (step 2) or the main loop (step 4) */
extern unsigned char quenched[NO_PORT];     /* receiver interrupts off after an overrun ... */
extern unsigned quench_t[NO_PORT];          /* ... since this tick */
extern unsigned char fresh[NO_PORT];        /* port reset and untouched since */
extern unsigned char rbt_seen[NO_PORT];     /* pflag[p] read RBT_USE since rbt_t ... */
extern unsigned rbt_t[NO_PORT];             /* ... without a chunk word from the main CPU */
/* statistics (read by tests and probes through the symbol map) */
extern unsigned n_good[NO_PORT], n_nak[NO_PORT], n_busy[NO_PORT], n_gap[NO_PORT];
extern unsigned n_sent[NO_PORT], n_retry[NO_PORT], n_fail[NO_PORT], n_coll[NO_PORT];
extern unsigned n_lerr[NO_PORT], n_break[NO_PORT], n_reset[NO_PORT], n_badmb;
extern unsigned n_stale[NO_PORT], n_quench[NO_PORT], n_deferred[NO_PORT];

/* isr.s: the interrupt paths (IR0..IR3) and what the main loop shares with them */
void tx_fill(int port);               /* step 12: fill the TX FIFO; IF = 0 */
void tx_retry(int port);              /* NAK / T1 while sending: back off or give up; IF = 0 */
void ger_update(int port);            /* GER from the port's state; IF = 0 */
void take_chunk(int port);            /* a chunk from the main CPU into the transmit ring; any IF */
void port_reset(int port, int notify);     /* ask for a port reset (deferred in step 2); any IF */
void port_reset_now(int port, int notify); /* ask for it whatever the step; any IF */
/* hw.c */
void pic_init(void);
void uart_init(int port);
void port_reinit(int port);
/* main.c */
void main_loop(void);
void mb_post(unsigned char word);

#endif
