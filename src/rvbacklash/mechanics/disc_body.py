def has_disc_fe(st):
    return False


def disc_body_compliance(*a):
    raise NotImplementedError
