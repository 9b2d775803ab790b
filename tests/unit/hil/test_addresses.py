"""udp://HOST:PORT parsing: clear errors for a bad scheme, host or port."""

import pytest

from railbrake.errors import InputError
from railbrake.hil import parse_udp_url


def test_numeric_and_named_hosts():
    assert parse_udp_url("udp://127.0.0.1:5000", "--bcu") == ("127.0.0.1", 5000)
    assert parse_udp_url("udp://localhost:65535", "--bcu") == ("127.0.0.1", 65535)
    assert parse_udp_url("udp://0.0.0.0:0", "--listen", allow_any_port=True) == ("0.0.0.0", 0)


@pytest.mark.parametrize("url, words", [
    ("tcp://127.0.0.1:5000", "expected udp://HOST:PORT"),
    ("udp://127.0.0.1", "expected udp://HOST:PORT"),
    ("udp://127.0.0.1:http", "port = 'http': must lie in [1, 65535]"),
    ("udp://127.0.0.1:0", "port = '0': must lie in [1, 65535]"),
    ("udp://127.0.0.1:70000", "70000"),
    ("udp://127.0.0.1:-3", "port = '-3'"),
    ("udp://:5000", "expected udp://HOST:PORT"),
    ("udp://no-such-host.invalid:5000", "host = 'no-such-host.invalid'"),
    ("udp://300.1.1.1:5000", "host = '300.1.1.1'"),
])
def test_bad_urls_name_the_option_and_the_problem(url, words):
    with pytest.raises(InputError, match="--bcu") as info:
        parse_udp_url(url, "--bcu")
    assert words in str(info.value)
