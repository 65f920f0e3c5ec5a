// Tests of the behavioural main CPU against a fake IDT7130 and a scripted comm CPU (comm_side.h):
// frame reassembly and dispatch, responses, tokens, port resets, ACK timeouts, mailbox words,
// configuration. The control cycle and the processor's timing are main_cpu_timing_test.cpp; the
// set-up both use is main_cpu_on_fakes.h.
#include "tests/main_cpu/main_cpu_on_fakes.h"

#include <string>
#include <vector>

using namespace rcsim;
using namespace rcsim::dpram_layout;
using namespace rcsim::test::main_cpu;
using rcsim::test::CommSide;
using sc_core::sc_time;

TEST(MainCpu, SingleChunkFrameIsReassembledAndDispatched) {
    MainCpuOnFakes b;
    b.comm.script = [](CommSide& c) { c.send_frame(1, cmd("EC", "hello")); };
    sc_core::sc_start(ms(5));
    ASSERT_EQ(b.cpu.received().size(), 1u);
    const FrameRecord& r = b.cpu.received()[0];
    EXPECT_EQ(r.port, 1u);
    EXPECT_EQ(r.token, "EC");
    EXPECT_EQ(r.data, "hello");
    EXPECT_EQ(b.cpu.port_stats(1).frames_received, 1u);
    EXPECT_EQ(b.cpu.port_stats(1).chunks_received, 1u);
    EXPECT_EQ(b.cpu.port_stats(1).bytes_received, cmd("EC", "hello").size());
    EXPECT_EQ(b.cpu.port_stats(0).frames_received, 0u);
    // The main CPU read the frame's only chunk, so it freed the area before its ACK word.
    const auto pflag_writes = b.ram.accesses_to(pflag_addr(1));
    ASSERT_FALSE(pflag_writes.empty());
    EXPECT_EQ(pflag_writes[0].kind, BusCycle::mem_write);
    EXPECT_EQ(pflag_writes[0].value, pflag_free);
    const auto acks = b.ram.writes_to(int2ext);
    ASSERT_FALSE(acks.empty());
    EXPECT_EQ(acks[0].value, word(kind_ack, 1));
    EXPECT_LT(pflag_writes[0].time, acks[0].time);
    // Every access is a right-port byte cycle.
    for (const auto& a : b.ram.log) EXPECT_EQ(a.initiator, 1);
}

TEST(MainCpu, EchoResponseComesBackThroughDpramWithPflagAndMailboxSequence) {
    MainCpuOnFakes b;
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(2, cmd("EC", "ping 42"));
        got = c.receive_frame(2);
    };
    sc_core::sc_start(ms(5));
    EXPECT_EQ(got.bytes, proto::encode({"EC", bch::ok, "ping 42"}));
    EXPECT_EQ(got.chunks, 1u);
    ASSERT_EQ(got.pflag_at_chunk.size(), 1u);
    EXPECT_EQ(got.pflag_at_chunk[0], pflag_rbt_use);
    EXPECT_EQ(b.pflag(2), pflag_free); // the comm CPU, reader of the last chunk, freed it
    // The response's right-port sequence: read pflag (free), write RBT_USE, chunk, word 0x12.
    const auto flag = b.ram.accesses_to(pflag_addr(2));
    ASSERT_EQ(flag.size(), 3u); // rx: free after reading; tx: read, then claim
    EXPECT_EQ(flag[1].kind, BusCycle::mem_read);
    EXPECT_EQ(flag[1].value, pflag_free);
    EXPECT_EQ(flag[2].kind, BusCycle::mem_write);
    EXPECT_EQ(flag[2].value, pflag_rbt_use);
    const auto words = b.ram.writes_to(int2ext);
    ASSERT_EQ(words.size(), 2u);
    EXPECT_EQ(words[1].value, word(kind_chunk, 2));
    const auto first_data = b.ram.accesses_to(data_addr(2));
    ASSERT_EQ(first_data.size(), 2u); // read by the handler, written by the response
    EXPECT_GT(first_data[1].time, flag[2].time);
    EXPECT_GT(words[1].time, first_data[1].time);
    EXPECT_EQ(b.cpu.port_stats(2).frames_sent, 1u);
    EXPECT_EQ(b.cpu.port_stats(2).chunks_sent, 1u);
    ASSERT_EQ(b.cpu.sent().size(), 1u);
    EXPECT_EQ(b.cpu.sent()[0].data, "ping 42");
}

TEST(MainCpu, ResponseIsNotInstantaneous) {
    MainCpuConfig c;
    c.command_time = us(300);
    MainCpuOnFakes b(c);
    b.comm.script = [&](CommSide& cs) {
        cs.send_frame(0, cmd("EC", "x"));
        cs.receive_frame(0);
    };
    sc_core::sc_start(ms(5));
    const auto words = b.ram.writes_to(int2ext);
    ASSERT_EQ(words.size(), 2u);
    EXPECT_GE(words[1].time - words[0].time, us(300));
}

TEST(MainCpu, ThreeThousandByteFrameCrossesInNineChunksBothWays) {
    MainCpuOnFakes b;
    std::string data;
    for (int i = 0; i < 2991; ++i) data += char(0x20 + (i * 7) % 95);
    const std::string wire = cmd("EC", data);
    ASSERT_EQ(wire.size(), 3000u);
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) {
        ASSERT_TRUE(c.send_frame(0, wire));
        got = c.receive_frame(0, ms(50));
    };
    sc_core::sc_start(ms(100));
    ASSERT_EQ(b.cpu.received().size(), 1u);
    EXPECT_EQ(b.cpu.received()[0].data, data);
    EXPECT_EQ(b.cpu.port_stats(0).chunks_received, 9u);
    EXPECT_EQ(got.bytes, wire); // the echo has BCH 00 too, so it is the same bytes
    EXPECT_EQ(got.chunks, 9u);
    for (auto f : got.pflag_at_chunk) EXPECT_EQ(f, pflag_rbt_use);
    EXPECT_EQ(b.cpu.port_stats(0).chunks_sent, 9u);
    EXPECT_EQ(b.cpu.port_stats(0).bytes_sent, 3000u);
    // The main CPU never writes a chunk before the previous one was ACKed: 9 chunk words, each
    // after an ACK word from the comm CPU (8 ACKs between them).
    unsigned chunk_words = 0;
    for (const auto& a : b.ram.writes_to(int2ext))
        if (a.value == word(kind_chunk, 0)) ++chunk_words;
    EXPECT_EQ(chunk_words, 9u);
}

TEST(MainCpu, MalformedFrameIsCountedAndNotDispatched) {
    MainCpuOnFakes b;
    std::string bad = cmd("EC", "abc");
    bad[bad.size() - 2] = bad[bad.size() - 2] == '0' ? '1' : '0'; // break the checksum
    int extra_word = 0;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(1, bad);
        extra_word = c.next_word(ms(3));
    };
    sc_core::sc_start(ms(5));
    EXPECT_EQ(b.cpu.port_stats(1).malformed, 1u);
    EXPECT_EQ(b.cpu.port_stats(1).frames_received, 0u);
    EXPECT_TRUE(b.cpu.received().empty());
    ASSERT_EQ(b.cpu.malformed().size(), 1u);
    EXPECT_NE(b.cpu.malformed()[0].reason.find("checksum"), std::string::npos);
    EXPECT_EQ(extra_word, -1); // no response frame
    EXPECT_EQ(b.pflag(1), pflag_free);
}

TEST(MainCpu, UnknownTokenAnswersBch01) {
    MainCpuOnFakes b;
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(0, cmd("QQ", "1"));
        got = c.receive_frame(0);
    };
    sc_core::sc_start(ms(5));
    const proto::Frame f = decoded(got.bytes);
    EXPECT_EQ(f.token, "QQ");
    EXPECT_EQ(f.bch, bch::unknown_token);
}

TEST(MainCpu, BadDataAnswersBch02) {
    MainCpuOnFakes b;
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(0, cmd("PW", "abc"));
        got = c.receive_frame(0);
    };
    sc_core::sc_start(ms(5));
    EXPECT_EQ(decoded(got.bytes).bch, bch::bad_data);
}

TEST(MainCpu, MotionTokenWithoutMotionInterfaceAnswersBch04) {
    MainCpuOnFakes b;
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(1, cmd("SV", "1"));
        got = c.receive_frame(1);
    };
    sc_core::sc_start(ms(5));
    const proto::Frame f = decoded(got.bytes);
    EXPECT_EQ(f.token, "SV");
    EXPECT_EQ(f.bch, bch::not_allowed);
}

TEST(MainCpu, MotionTokenReachesTheMotionInterfaceAndControlCycleRuns) {
    MainCpuOnFakes b;
    FakeMotion m;
    b.cpu.set_motion(&m);
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(0, cmd("MA", "1,1000,50,10,10"));
        got = c.receive_frame(0);
    };
    sc_core::sc_start(ms(5) + us(1));
    ASSERT_EQ(m.commands.size(), 1u);
    EXPECT_EQ(m.commands[0].first, "MA");
    EXPECT_EQ(m.commands[0].second, "1,1000,50,10,10");
    const proto::Frame f = decoded(got.bytes);
    EXPECT_EQ(f.bch, bch::ok);
    EXPECT_EQ(f.data, "accepted");
    // Cycles at 0..5 ms, each at its actual start time.
    ASSERT_EQ(m.cycles.size(), 6u);
    EXPECT_EQ(m.cycles.size(), b.cpu.control_cycles());
    for (std::size_t k = 0; k < m.cycles.size(); ++k) EXPECT_GE(m.cycles[k], ms(k));
}

TEST(MainCpu, ProgramUploadAndDownloadSpanSeveralChunks) {
    MainCpuOnFakes b;
    std::string text;
    for (int i = 0; i < 120; ++i) text += "MOVL P" + std::to_string(i) + ",V=100;";
    ASSERT_GT(text.size(), 2 * chunk_size);
    test::ReceivedByComm up, down;
    b.comm.script = [&](CommSide& c) {
        ASSERT_TRUE(c.send_frame(2, cmd("PU", "weld," + text)));
        up = c.receive_frame(2);
        ASSERT_TRUE(c.send_frame(2, cmd("PD", "weld")));
        down = c.receive_frame(2, ms(20));
    };
    sc_core::sc_start(ms(40));
    EXPECT_EQ(up.bytes, proto::encode({"PU", bch::ok, ""}));
    EXPECT_EQ(down.bytes, proto::encode({"PD", bch::ok, text}));
    EXPECT_GE(down.chunks, 3u);
    EXPECT_EQ(b.cpu.dispatcher().programs().at("weld"), text);
}

TEST(MainCpu, ResetWordMidFrameDropsThePartialFrame) {
    MainCpuOnFakes b;
    const std::string first = cmd("EC", std::string(600, 'a')); // two chunks
    const std::string second = cmd("EC", "fresh");
    b.comm.script = [&](CommSide& c) {
        c.put_chunk(0, first.substr(0, chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 0), ms(2)));
        c.ram().left_write(pflag_addr(0), pflag_free); // the firmware frees the area on reset
        c.post_word(word(kind_reset, 0));
        c.send_frame(0, second);
    };
    sc_core::sc_start(ms(5));
    EXPECT_EQ(b.cpu.port_stats(0).resets_received, 1u);
    EXPECT_EQ(b.cpu.port_stats(0).partial_dropped, 1u);
    EXPECT_EQ(b.cpu.port_stats(0).malformed, 0u);
    ASSERT_EQ(b.cpu.received().size(), 1u);
    EXPECT_EQ(b.cpu.received()[0].data, "fresh");
}

TEST(MainCpu, ResetWordAbortsTheResponseInFlight) {
    MainCpuConfig c;
    c.ack_timeout = ms(20);
    MainCpuOnFakes b(c);
    b.comm.script = [&](CommSide& cs) {
        cs.send_frame(0, cmd("EC", std::string(1000, 'z'))); // response needs 4 chunks
        ASSERT_TRUE(cs.expect_word(word(kind_chunk, 0), ms(2)));
        cs.ram().left_write(pflag_addr(0), pflag_free);
        cs.post_word(word(kind_reset, 0)); // instead of the ACK
    };
    sc_core::sc_start(ms(40));
    EXPECT_EQ(b.cpu.port_stats(0).tx_aborted, 1u);
    EXPECT_EQ(b.cpu.port_stats(0).frames_sent, 0u);
    EXPECT_EQ(b.cpu.port_stats(0).ack_timeouts, 0u);
    unsigned chunk_words = 0;
    for (const auto& a : b.ram.writes_to(int2ext)) chunk_words += a.value == word(kind_chunk, 0);
    EXPECT_EQ(chunk_words, 1u);
}

TEST(MainCpu, ResponseWaitsWhileTheCommCpuHoldsTheArea) {
    MainCpuOnFakes b;
    sc_time freed;
    b.comm.script = [&](CommSide& c) {
        c.send_frame(0, cmd("EC", "later"));
        c.ram().left_write(pflag_addr(0), pflag_ext_use); // a host frame is arriving meanwhile
        sc_core::wait(ms(2));
        freed = sc_core::sc_time_stamp();
        c.ram().left_write(pflag_addr(0), pflag_free);
        c.receive_frame(0);
    };
    sc_core::sc_start(ms(5));
    EXPECT_EQ(b.cpu.port_stats(0).frames_sent, 1u);
    unsigned claims = 0;
    for (const auto& a : b.ram.log) {
        if (a.kind == BusCycle::mem_write && a.addr == pflag_addr(0) && a.value == pflag_rbt_use) {
            EXPECT_GE(a.time, freed);
            ++claims;
        }
    }
    EXPECT_EQ(claims, 1u);
    for (const auto& a : b.ram.accesses_to(data_addr(0))) {
        if (a.kind == BusCycle::mem_write) {
            EXPECT_GE(a.time, freed);
        }
    }
}

TEST(MainCpu, AckTimeoutAbandonsTheFrameFreesTheAreaAndResetsThePort) {
    MainCpuConfig c;
    c.ack_timeout = ms(5);
    MainCpuOnFakes b(c);
    b.comm.script = [&](CommSide& cs) {
        cs.send_frame(1, cmd("EC", "never acked"));
        ASSERT_TRUE(cs.expect_word(word(kind_chunk, 1), ms(2)));
        ASSERT_TRUE(cs.expect_word(word(kind_reset, 1), ms(10)));
    };
    sc_core::sc_start(ms(20));
    EXPECT_EQ(b.cpu.port_stats(1).ack_timeouts, 1u);
    EXPECT_EQ(b.cpu.port_stats(1).frames_sent, 0u);
    EXPECT_EQ(b.cpu.port_stats(1).resets_sent, 1u);
    EXPECT_EQ(b.pflag(1), pflag_free);
    const auto words = b.ram.writes_to(int2ext);
    ASSERT_EQ(words.size(), 3u); // ACK of the command, the chunk, the reset
    EXPECT_GE(words[2].time - words[1].time, ms(5));
}

TEST(MainCpu, RequestedPortResetSendsTheResetWord) {
    MainCpuOnFakes b;
    bool seen = false;
    b.comm.script = [&](CommSide& c) { seen = c.expect_word(word(kind_reset, 2), ms(1)); };
    b.cpu.request_port_reset(2);
    sc_core::sc_start(ms(2));
    EXPECT_TRUE(seen);
    EXPECT_EQ(b.cpu.port_stats(2).resets_sent, 1u);
}

TEST(MainCpu, ControllerInitiatedFrameIsSent) {
    MainCpuOnFakes b;
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& c) { got = c.receive_frame(1); };
    b.cpu.send(1, "ST", "ALARM,3");
    sc_core::sc_start(ms(2));
    EXPECT_EQ(got.bytes, proto::encode({"ST", 0, "ALARM,3"}));
}

TEST(MainCpu, SendRejectsBadPortAndBadFrameNamingTheValue) {
    MainCpuOnFakes b;
    try {
        b.cpu.send(3, "EC", "");
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("port 3"), std::string::npos) << e.what();
    }
    EXPECT_THROW(b.cpu.send(0, "E", ""), std::invalid_argument);
    EXPECT_THROW(b.cpu.request_port_reset(7), std::invalid_argument);
}

TEST(MainCpu, UnknownMailboxWordIsCountedAndIgnored) {
    MainCpuOnFakes b;
    b.comm.script = [](CommSide& c) {
        c.post_word(0x47);
        c.post_word(0x13); // port 3 does not exist
        c.send_frame(0, cmd("EC", "ok"));
    };
    sc_core::sc_start(ms(2));
    EXPECT_EQ(b.cpu.unknown_words(), 2u);
    EXPECT_EQ(b.cpu.port_stats(0).frames_received, 1u);
}

TEST(MainCpu, ThreePortsInterleavedStayApart) {
    MainCpuOnFakes b;
    const std::string a = cmd("EC", std::string(500, 'a'));
    const std::string c2 = cmd("EC", std::string(500, 'c'));
    std::vector<test::ReceivedByComm> got(3);
    b.comm.script = [&](CommSide& c) {
        // First chunks of ports 0 and 2 interleaved, then the rest, then a short one on port 1.
        c.put_chunk(0, a.substr(0, chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 0), ms(2)));
        c.put_chunk(2, c2.substr(0, chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 2), ms(2)));
        c.put_chunk(0, a.substr(chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 0), ms(2)));
        c.put_chunk(2, c2.substr(chunk_size));
        ASSERT_TRUE(c.expect_word(word(kind_ack, 2), ms(2)));
        c.send_frame(1, cmd("EC", "b"));
        got[0] = c.receive_frame(0);
        got[2] = c.receive_frame(2);
        got[1] = c.receive_frame(1);
    };
    sc_core::sc_start(ms(20));
    EXPECT_EQ(got[0].bytes, a);
    EXPECT_EQ(got[1].bytes, cmd("EC", "b"));
    EXPECT_EQ(got[2].bytes, c2);
    for (unsigned p = 0; p < 3; ++p) EXPECT_EQ(b.cpu.port_stats(p).frames_sent, 1u) << p;
}

TEST(MainCpu, MailboxGapSpacesInt2extWords) {
    MainCpuConfig c;
    c.mailbox_gap = us(400);
    MainCpuOnFakes b(c);
    b.comm.script = [&](CommSide& cs) {
        cs.put_chunk(0, cmd("EC", "a"));
        cs.put_chunk(1, cmd("EC", "b")); // its ACK word would follow the first ACK at once
        ASSERT_TRUE(cs.expect_word(word(kind_ack, 0), ms(2)));
        ASSERT_TRUE(cs.expect_word(word(kind_ack, 1), ms(2)));
        cs.receive_frame(0);
        cs.receive_frame(1);
    };
    sc_core::sc_start(ms(10));
    const auto words = b.ram.writes_to(int2ext);
    ASSERT_GE(words.size(), 4u);
    for (std::size_t i = 1; i < words.size(); ++i) EXPECT_GE(words[i].time - words[i - 1].time, us(400));
    EXPECT_EQ(b.cpu.port_stats(0).frames_sent, 1u);
    EXPECT_EQ(b.cpu.port_stats(1).frames_sent, 1u);
}

// docs/system.md §4.3: int2ext is a single byte, so a word the comm CPU has not read is
// overwritten by the next.
// This documents the hazard that mailbox_gap and mailbox_handshake exist for.
TEST(MainCpu, WithoutHandshakeAnUnreadInt2extWordIsOverwritten) {
    MainCpuConfig c;
    c.ack_timeout = ms(5);
    c.mailbox_handshake = false;
    MainCpuOnFakes b(c);
    b.comm.handshake = false;
    b.comm.script = [&](CommSide& cs) {
        cs.put_chunk(0, cmd("EC", "a"));
        cs.put_chunk(1, cmd("EC", "b"));
        sc_core::wait(ms(2)); // a slow comm CPU: both ACKs and both response words are written
        for (int w; (w = cs.next_word(us(100))) >= 0;) {
        }
    };
    sc_core::sc_start(ms(3));
    // Four words were written (two ACKs, two chunk words) but the comm CPU could read only one.
    EXPECT_EQ(b.ram.writes_to(int2ext).size(), 4u);
    EXPECT_EQ(b.comm.words.size(), 1u);
}

TEST(MainCpu, WithoutHandshakeTheExchangeWorksWhileTheCommCpuKeepsUp) {
    MainCpuConfig c;
    c.mailbox_handshake = false;
    MainCpuOnFakes b(c);
    b.comm.handshake = false;
    test::ReceivedByComm got;
    b.comm.script = [&](CommSide& cs) {
        cs.send_frame(0, cmd("EC", "plain"));
        got = cs.receive_frame(0);
    };
    sc_core::sc_start(ms(3));
    EXPECT_EQ(got.bytes, cmd("EC", "plain"));
    // No handshake traffic: int2ext is only written, int2rbt only read.
    for (const auto& a : b.ram.log) {
        if (a.addr == int2ext) {
            EXPECT_EQ(a.kind, BusCycle::mem_write);
        }
        if (a.addr == int2rbt) {
            EXPECT_EQ(a.kind, BusCycle::mem_read);
        }
    }
}

TEST(MainCpu, MailboxHandshakeLosesNoWordWithASlowCommCpu) {
    MainCpuOnFakes b; // the handshake is the default on both sides
    std::vector<test::ReceivedByComm> got(2);
    b.comm.script = [&](CommSide& cs) {
        cs.put_chunk(0, cmd("EC", "a"));
        cs.put_chunk(1, cmd("EC", "b")); // written as soon as the main CPU cleared int2rbt
        sc_core::wait(ms(2));             // slow: the main CPU must hold its next words back
        ASSERT_TRUE(cs.expect_word(word(kind_ack, 0), ms(1)));
        ASSERT_TRUE(cs.expect_word(word(kind_ack, 1), ms(1)));
        got[0] = cs.receive_frame(0);
        got[1] = cs.receive_frame(1);
    };
    sc_core::sc_start(ms(10));
    EXPECT_EQ(got[0].bytes, cmd("EC", "a"));
    EXPECT_EQ(got[1].bytes, cmd("EC", "b"));
    EXPECT_EQ(b.cpu.mailbox_overwrites(), 0u);
    // Every int2ext word was written while the mailbox read 0, and the handler cleared int2rbt.
    const auto& log = b.ram.log;
    for (std::size_t i = 0; i < log.size(); ++i) {
        if (log[i].kind != BusCycle::mem_write || log[i].addr != int2ext) continue;
        ASSERT_GT(i, 0u);
        EXPECT_EQ(log[i - 1].addr, int2ext);
        EXPECT_EQ(log[i - 1].kind, BusCycle::mem_read);
        EXPECT_EQ(log[i - 1].value, 0);
    }
    unsigned clears = 0;
    for (const auto& a : log) clears += a.kind == BusCycle::mem_write && a.addr == int2rbt && a.value == 0;
    EXPECT_EQ(clears, 4u); // two chunk words, two ACK words from the comm CPU
}

TEST(MainCpu, MailboxHandshakeGivesUpAfterTheTimeoutAndCountsIt) {
    MainCpuConfig c;
    c.mailbox_handshake = true;
    c.ack_timeout = ms(3);
    MainCpuOnFakes b(c);
    b.ram.mem[int2ext] = 0x55; // a comm CPU that never clears its mailbox
    b.comm.script = [&](CommSide& cs) { cs.post_word(word(kind_chunk, 0)); };
    b.ram.mem[data_addr(0)] = proto::ETX; // a one-byte (malformed) frame, answered by an ACK
    sc_core::sc_start(ms(5));
    EXPECT_EQ(b.cpu.mailbox_overwrites(), 1u);
    EXPECT_EQ(b.ram.mem[int2ext], word(kind_ack, 0));
}

TEST(MainCpu, OverlongFrameIsDrainedAndCountedAsMalformed) {
    MainCpuOnFakes b;
    // 8202 bytes without an ETX until the end: one over the limit.
    std::string huge = cmd("EC", std::string(proto::max_data, 'q'));
    huge.insert(6, "q");
    b.comm.script = [&](CommSide& c) { EXPECT_TRUE(c.send_frame(0, huge)); };
    sc_core::sc_start(ms(200));
    EXPECT_EQ(b.cpu.port_stats(0).malformed, 1u);
    EXPECT_EQ(b.cpu.port_stats(0).chunks_received, (huge.size() + chunk_size - 1) / chunk_size);
    ASSERT_EQ(b.cpu.malformed().size(), 1u);
    EXPECT_NE(b.cpu.malformed()[0].reason.find("longer"), std::string::npos);
}

TEST(MainCpu, ReportHoldsJitterAndPortCounters) {
    MainCpuOnFakes b;
    b.comm.script = [](CommSide& c) {
        c.send_frame(0, cmd("EC", "r"));
        c.receive_frame(0);
    };
    sc_core::sc_start(ms(3) - us(1));
    const nlohmann::json j = b.cpu.report();
    EXPECT_EQ(j["cycle_jitter_us"]["count"], 3);
    EXPECT_EQ(j["ports"][0]["frames_received"], 1);
    EXPECT_EQ(j["ports"][0]["frames_sent"], 1);
    EXPECT_EQ(j["ports"].size(), 3u);
    EXPECT_GT(j["cpu_busy_us"].get<double>(), 0.0);
}

TEST(MainCpuConfig, RejectsBadValuesNamingThem) {
    auto message = [](const MainCpuConfig& c) {
        try {
            c.validate();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    MainCpuConfig c;
    EXPECT_EQ(message(c), "no error");
    c.cycle_time = c.cycle_period;
    EXPECT_NE(message(c).find("cycle_time"), std::string::npos) << message(c);
    c = MainCpuConfig();
    c.bus_clock_hz = 0;
    EXPECT_NE(message(c).find("bus_clock_hz 0"), std::string::npos);
    c = MainCpuConfig();
    c.access_cycles = 0;
    EXPECT_NE(message(c).find("access_cycles 0"), std::string::npos);
    c = MainCpuConfig();
    c.ack_timeout = sc_core::SC_ZERO_TIME;
    EXPECT_NE(message(c).find("ack_timeout"), std::string::npos);
    c = MainCpuConfig();
    c.poll_interval = sc_core::SC_ZERO_TIME;
    EXPECT_NE(message(c).find("poll_interval"), std::string::npos);
}

TEST(MainCpuConfig, ModuleRefusesABadConfig) {
    MainCpuConfig c;
    c.cycle_period = sc_core::SC_ZERO_TIME;
    EXPECT_THROW(MainCpu("bad", c), std::invalid_argument);
}
