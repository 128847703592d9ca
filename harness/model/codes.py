"""The CP 341 STATUS event codes (Table 8-1, classes 00..0A, and Table 8-2, class 1E): the
one list of codes, used by the models, the catalogue (ptpcert.status adds the texts) and the
fuzzer. A code is 16#CCNN: event class CC, event number NN."""

from __future__ import annotations

from enum import IntEnum


class Code(IntEnum):
    # -- class 00: start-up
    PARAMS_TAKEN_OVER = 0x0003
    PARAMS_ALREADY_IN_CP = 0x0004
    CPU_TO_STOP = 0x0007
    CPU_TO_RUN = 0x0008
    # -- class 01: hardware fault on the CP
    EPROM_TEST_FAILED = 0x0101
    RAM_TEST_FAILED = 0x0102
    INTERFACE_QUERY_FAILED = 0x0103
    FIRMWARE_ERROR = 0x0110
    # -- class 02: initialization error
    PARAMS_REJECTED = 0x020F
    # -- class 03: FB parameters
    INVALID_FB_PARAMETERS = 0x0301
    # -- class 04: CP-CPU data traffic
    ILLEGAL_DATA_TYPE = 0x0403
    CPU_TRANSFER_FAILED = 0x0407
    RECEIVE_HANDOVER_DELAYED = 0x0408
    RECEIVED_DATA_CANCELLED = 0x0409
    TRANSFER_CANCELLED_BY_RESET = 0x040A
    # -- class 05: processing a CPU request (RK 512, active side)
    ABORTED_BY_CP_RESTART = 0x0501
    NOT_ALLOWED_IN_MODE = 0x0502
    ADDRESS_OUT_OF_RANGE = 0x0514
    INVALID_FLAG_BIT = 0x0515
    CPU_NUMBER_TOO_HIGH = 0x0516
    LENGTH_INVALID_FOR_CP = 0x0517
    COMMAND_NOT_SENT = 0x051A
    # -- class 06: processing a partner request (RK 512, passive side)
    CMD_BYTE1_INVALID = 0x0601
    CMD_BYTE3_INVALID = 0x0602
    CMD_BYTE3_CHANGED = 0x0603
    CMD_BYTE4_INVALID = 0x0604
    CMD_BYTE4_CHANGED = 0x0605
    DB_NUMBER_NOT_ALLOWED = 0x0606
    START_ADDRESS_TOO_HIGH = 0x0607
    LENGTH_NOT_ALLOWED = 0x0608
    FLAG_INVALID = 0x0609
    CPU_NUMBER_NOT_ALLOWED = 0x060A
    SEND_LENGTH_DIFFERS = 0x060B
    FETCH_WITH_DATA = 0x060C
    CP_NOT_READY = 0x060D
    PARTNER_SEQUENCE_ERROR = 0x060E
    DB_LOCKED = 0x060F
    FRAME_TOO_SHORT = 0x0610
    FRAME_LENGTH_DIFFERS = 0x0611
    RESPONSE_NOT_SENT = 0x0612
    # -- class 07: send errors
    FIRST_REPETITION = 0x0701
    SETUP_REFUSED = 0x0702
    SETUP_TIMEOUT = 0x0703
    SEND_INTERRUPTED = 0x0704
    RELEASE_REFUSED = 0x0706
    RELEASE_TIMEOUT = 0x0707
    XON_CTS_WAIT_EXPIRED = 0x0708
    SETUP_ATTEMPTS_EXCEEDED = 0x0709
    TX_ATTEMPTS_EXCEEDED = 0x070A
    # -- class 08: receive errors
    EXPECT_REPETITION = 0x0801
    RX_SETUP_ERROR = 0x0802
    RX_LOGICAL_ERROR = 0x0805
    CDT_EXCEEDED = 0x0806
    BCC_ERROR = 0x0808
    NO_RECEIVE_BUFFER = 0x080A
    CHARACTER_ERROR = 0x080C
    LINE_BREAK = 0x080D
    ATTEMPTS_MISMATCH = 0x0815
    FRAME_TOO_LONG = 0x0816
    DSR_CTS_DROPPED = 0x0818
    # -- class 09: error number in the partner's response frame (REATEL, Table 8-3)
    PARTNER_MEMORY_ACCESS = 0x0902
    PARTNER_DB_ACCESS = 0x0903
    PARTNER_REQUEST_NOT_PERMITTED = 0x0904
    PARTNER_TYPE_OR_PLC_FAULT = 0x0905
    PARTNER_SEQUENCE = 0x0908
    PARTNER_DB_LOCKED = 0x0909
    PARTNER_HEADER_BYTE3 = 0x090A
    PARTNER_HEADER_BYTE1_4 = 0x090B
    PARTNER_FRAME_LENGTH = 0x090C
    PARTNER_NO_RESTART = 0x090D
    PARTNER_UNKNOWN_ERROR = 0x090E
    # -- class 0A: errors in the partner's response frame found by the CP
    RESPONSE_OUT_OF_SEQUENCE = 0x0A01
    RESPONSE_STRUCTURE = 0x0A02
    RESPONSE_DATA_LENGTH = 0x0A03
    RESPONSE_TO_SEND_WITH_DATA = 0x0A04
    RESPONSE_TIMEOUT = 0x0A05
    # -- class 1E (Table 8-2)
    ABORTED_BY_RESET = 0x1E0D
    RD_REC_ERROR = 0x1E0E
    WR_REC_ERROR = 0x1E0F
    LEN_ILLEGAL = 0x1E41

    @property
    def text(self) -> str:
        """The manual's notation, ``16#0703``."""
        return f"16#{self.value:04X}"

    @property
    def event_class(self) -> int:
        return self.value >> 8
