/*
 * rcsim communication firmware -- 8259A and 82510 set-up, port reset.
 */
#include "fw.h"

/* 8259A: edge triggered, single, vectors 0x20..0x27, 8086 mode; IR0..IR3 enabled. */
void pic_init(void)
{
    outb(PIC_A0, PIC_ICW1);
    outb(PIC_A1, PIC_ICW2);
    outb(PIC_A1, PIC_ICW4);
    outb(PIC_A1, PIC_OCW1);
}

/*
 * 82510 channel set-up: software reset, 9600 bps 8E1 (BRGA divisor 60 at 18.432 MHz),
 * 4-byte RX FIFO with threshold 1, receive errors and BREAK as Rx machine sources; on TICK_PORT
 * also BRGB as the 1 ms timer.  Leaves GER = 0 (the software reset clears it: the channel asks
 * for nothing; ger_update turns its sources on) and bank 1 (WORK) selected, the bank the main
 * loop and the ISRs work in.  Any IF: with GER = 0 the port's handler finds nothing pending,
 * and it restores the bank it found (isr.s _rs232_isr), so the other ports' interrupts -- and
 * this port's stray one -- may run between two writes (docs/firmware.md "Faults and the rule").
 */
void uart_init(int port)
{
    unsigned b = UART_BASE(port);
    int tick = (port == TICK_PORT);

    outb(b + U_BANK, BANK_WORK);
    outb(b + U_ICM, ICM_RESET);

    /* bank 0: line format and BRGA divisor */
    outb(b + U_BANK, BANK_NAS);
    outb(b + U_LCR, LCR_DLAB | port_lcr[port]);
    outb(b + U_BAL, port_div[port] & 0xFF);
    outb(b + U_BAH, port_div[port] >> 8);
    if (tick) {
        /* BRGB divisor: bank 3 offsets 0/1 while DLAB = 1 */
        outb(b + U_BANK, BANK_MODM);
        outb(b + U_BBL, tick_div & 0xFF);
        outb(b + U_BBH, tick_div >> 8);
        outb(b + U_BANK, BANK_NAS);
    }
    outb(b + U_LCR, port_lcr[port]);
    outb(b + U_MCR, MCR_ON);

    /* bank 2: FIFO thresholds 0 (interrupt at 1 byte), normal modes, RX error interrupts */
    outb(b + U_BANK, BANK_GEN);
    outb(b + U_FMD, 0x00);
    outb(b + U_TMD, 0x00);
    outb(b + U_IMD, 0x00);
    outb(b + U_RIE, RIE_ERRS);
    outb(b + U_RMD, 0x00);

    /* bank 3: clocks from BRGA x16, BRGA = baud-rate generator, BRGB = timer */
    outb(b + U_BANK, BANK_MODM);
    outb(b + U_CLCF, CLCF_BRGA16);
    outb(b + U_BACF, BACF_BRG);
    outb(b + U_BBCF, BBCF_TIMER);
    outb(b + U_MIE, 0x00);
    outb(b + U_TMIE, tick ? TMIE_TB : 0x00);

    /* bank 1: enable receiver and transmitter (flushing both), clear status, start the timer */
    outb(b + U_BANK, BANK_WORK);
    outb(b + U_RCM, RCM_START);
    outb(b + U_TCM, TCM_START);
    outb(b + U_ICM, ICM_STC);
    if (tick)
        outb(b + U_TMCR, TMCR_GO_B);
}

/*
 * The reset of a port in step 4 (ST_RESET), from the main loop only, IF = 1.  Step 4 keeps every
 * other path off the port meanwhile: its GER asks for nothing but the tick (ger_update), the
 * per-character code only NAKs an ENQ, the main loop runs nothing else of it, port_reset only
 * adds its notify bit.  So the receive state and the 82510 are done with interrupts enabled;
 * only the transmit ring, which the mailbox handler's chunk copy also changes (take_chunk), and
 * the way back to step 0 are done with IF = 0.  Drops both buffers, frees pflag[p] and, if
 * reset_due says so, tells the main CPU with a 0x3p word in int2rbt.
 */
void port_reinit(int port)
{
    unsigned f;

    quenched[port] = 0;
    txe_wait[port] = 0;
    rx_len[port] = 0;
    rx_fwd[port] = 0;
    rx_bad[port] = 0;
    chunk_out[port] = 0;
    tx_try[port] = 0;
    tx_whole[port] = 0;
    uart_init(port);

    /* One step for the mailbox handler's chunk copy: a chunk it began before is dropped (gen),
     * one it begins after goes into the empty ring, and its ACK word follows our 0x3p. */
    f = irq_off();
    ++gen[port];
    chunk_pending[port] = 0;
    tx_have[port] = 0;
    tx_rd[port] = 0;
    tx_wr[port] = 0;
    tx_used[port] = 0;
    tx_part[port] = 0;
    dp_wr(PFLAG(port), P_FREE);
    if (reset_due[port] & 2)
        mb_post(MB_RESET | port);
    irq_restore(f);

    f = irq_off();
    reset_due[port] = 0;
    fresh[port] = 1;
    step[port] = ST_IDLE;
    ger_update(port);                   /* the receiver (and the tick) on again */
    irq_restore(f);
    ++n_reset[port];
}
