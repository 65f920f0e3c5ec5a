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
 * 4-byte RX FIFO with threshold 1, interrupts on received data and on receive errors and
 * BREAK; on TICK_PORT also BRGB as the 1 ms timer.  Leaves bank 1 (WORK) selected, which is
 * the bank the main loop and the ISRs work in.  Call with interrupts disabled.
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

    /* bank 0: interrupt enables, then back to the working bank */
    outb(b + U_BANK, BANK_NAS);
    outb(b + U_GER, GER_ON(port));
    outb(b + U_BANK, BANK_WORK);
}

/*
 * GER of one 82510 (bank 0, from bank 1 and back), from the port's state: the receiver's
 * sources unless it is quenched, the tick on TICK_PORT, the Tx FIFO while a frame goes out
 * (step 12), the Tx machine while a timer waits for the transmitter to be idle.  IF = 0.
 */
void ger_update(int port)
{
    unsigned g = port == TICK_PORT ? GER_TIMER : 0;  /* words: a byte local makes SP odd */

    if (!quenched[port])
        g |= GER_RX;
    if (step[port] == ST_SEND)
        g |= GER_TXF;
    if (txe_wait[port])
        g |= GER_TXM;
    uart_ger(UART_BASE(port), g);
}

/*
 * Port reset: re-initialise the 82510 channel, drop both buffers and the state, free pflag[p].
 * `notify' also tells the main CPU with a 0x3p word in int2rbt.
 */
void port_reinit(int port, int notify)
{
    unsigned f = irq_off();

    step[port] = ST_IDLE;
    quenched[port] = 0;
    txe_wait[port] = 0;
    reset_due[port] = 0;
    uart_init(port);
    rx_len[port] = 0;
    rx_fwd[port] = 0;
    rx_bad[port] = 0;
    chunk_out[port] = 0;
    chunk_pending[port] = 0;
    tx_have[port] = 0;
    tx_rd[port] = 0;
    tx_wr[port] = 0;
    tx_used[port] = 0;
    tx_part[port] = 0;
    tx_try[port] = 0;
    tx_whole[port] = 0;
    ++gen[port];
    dp_wr(PFLAG(port), P_FREE);
    if (notify)
        mb_post(MB_RESET | port);
    fresh[port] = 1;
    ++n_reset[port];
    irq_restore(f);
}

/*
 * A port reset is asked for (mailbox word 0x3p from the main CPU, BREAK on the line).  A frame
 * we have answered with EOT (step 2, being handed to the main CPU) is a promise of delivery: the
 * reset then waits until its last chunk has been consumed (to_dpram calls port_reinit); the
 * port answers ENQ with NAK meanwhile.  Any IF.
 */
void port_reset(int port, int notify)
{
    unsigned f = irq_off();

    if (step[port] == ST_DONE) {
        if (!reset_due[port])
            ++n_deferred[port];
        reset_due[port] |= notify ? 3 : 1;
    } else {
        port_reinit(port, notify);
    }
    irq_restore(f);
}
