"""Byte-level agreement helper: pymavlink encodes or decodes what the Rust test asks for.

Usage: python pymav_roundtrip.py encode|decode < request.json > answer.json
encode: request = [{"name", "fields": {..}, "seq", "sys", "comp", "v": 1|2}], answer = [hex, ...]
decode: request = [{"hex", "v"}], answer = [{"name", "fields": {..}}, ...]
"""
import json
import sys

from pymavlink.dialects.v10 import ardupilotmega as mav1
from pymavlink.dialects.v20 import ardupilotmega as mav2


def module(v):
    return mav1 if v == 1 else mav2


def encode(req):
    out = []
    for r in req:
        m = module(r["v"])
        cls = getattr(m, "MAVLink_%s_message" % r["name"].lower())
        kwargs = {}
        # array_lengths follows the wire order (ordered_fieldnames), fieldtypes the XML order.
        lengths = dict(zip(cls.ordered_fieldnames, cls.array_lengths))
        for i, f in enumerate(cls.fieldnames):
            t = cls.fieldtypes[i]
            n = lengths[f]
            given = r["fields"].get(f)
            if t == "char":
                kwargs[f] = (given or "").encode()
            elif n:
                vals = list(given) if isinstance(given, list) else ([given] if given is not None else [])
                kwargs[f] = vals + [0] * (n - len(vals))
            elif t in ("float", "double"):
                kwargs[f] = float(given if given is not None else 0)
            else:
                kwargs[f] = int(given if given is not None else 0)
        msg = cls(**kwargs)
        link = m.MAVLink(None, srcSystem=r["sys"], srcComponent=r["comp"])
        link.seq = r["seq"]
        out.append(bytes(msg.pack(link)).hex())
    return out


def decode(req):
    out = []
    for r in req:
        m = module(r["v"])
        link = m.MAVLink(None)
        link.robust_parsing = False
        msg = link.decode(bytearray(bytes.fromhex(r["hex"])))
        d = msg.to_dict()
        name = d.pop("mavpackettype")
        out.append({"name": name, "fields": d})
    return out


if __name__ == "__main__":
    req = json.load(sys.stdin)
    res = encode(req) if sys.argv[1] == "encode" else decode(req)
    json.dump(res, sys.stdout)
