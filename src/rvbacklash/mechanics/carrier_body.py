def has_carrier_fe(st):
    return False


def carrier_body_compliance(*a):
    raise NotImplementedError
